// report.md section 4: the paper's texture and environment findings, tested over pairs of data sets that differ only
// in that attribute (the same layout and the other attribute), by the verdict rules of docs/statistics.md
// ("Verdicts"): a difference needs the exact paired test to reject after Holm's correction, an equality needs the
// sign test to put the median, and the bootstrap interval the mean, within +-0.01 AUC; otherwise "not shown".
#include <map>

#include "occsweep/sweeps/compare_statistics.hpp"
#include "reproduce_internal.hpp"

namespace occsweep::reproduce {
using nlohmann::json;

namespace {

constexpr double kSmallestAucDifference = 0.01;  // the differences docs/fidelity.md called "equal within 0.01"

struct GroupFinding {
  const char* attribute;  // the rows' field
  const char* better;     // the paper's better group
  const char* worse;
};
constexpr GroupFinding kFindings[] = {{"texture", "voronoi", "plain"}, {"environment", "building", "parking"}};
constexpr const char* kMethods[] = {"octomap", "knn"};

// The mean best AUC of `method` over each data set's sets in `group`, keyed by the data set's name with the group
// taken out: the key its partner in the other group has.
std::map<std::string, double> groupMeans(const json& rows, const char* truth, const char* method, const char* attribute,
                                         const std::string& group) {
  std::map<std::string, std::pair<double, int>> sums;
  for (const json& r : rows) {
    const json& side = truth ? r.at("truths").at(truth) : r;
    if (r.at(attribute) != group || side.at(method).is_null()) continue;
    std::string key = r.at("dataset").get<std::string>();
    if (const auto at = key.find(group); at != std::string::npos) key.erase(at, group.size());
    auto& [sum, n] = sums[key];
    sum += get(side.at(method).at("auc")), ++n;
  }
  std::map<std::string, double> means;
  for (const auto& [key, s] : sums) means[key] = s.first / s.second;
  return means;
}

// The bootstrap and rules of compare, with the smallest AUC difference of interest.
CompareStatisticsOptions groupOptions() {
  CompareStatisticsOptions options;
  options.rules.smallest_effect = kSmallestAucDifference;
  return options;
}

// better - worse over the pairs of data sets that differ only in the finding's attribute.
DatasetComparison pairedGroups(const json& rows, const char* truth, const char* method, const GroupFinding& f) {
  const auto better = groupMeans(rows, truth, method, f.attribute, f.better),
             worse = groupMeans(rows, truth, method, f.attribute, f.worse);
  std::vector<std::string> pairs;
  std::vector<double> differences;
  for (const auto& [key, auc] : better)
    if (const auto other = worse.find(key); other != worse.end())
      pairs.push_back(key), differences.push_back(auc - other->second);
  return pairedComparison(std::move(pairs), std::move(differences), groupOptions());
}

std::string findingVerdict(const std::vector<const DatasetComparison*>& methods, const GroupFinding& f) {
  std::size_t gains = 0, losses = 0, equal = 0;
  for (const DatasetComparison* c : methods) {
    gains += c->verdict.kind == stats::VerdictKind::Gain;
    losses += c->verdict.kind == stats::VerdictKind::Loss;
    equal += c->verdict.kind == stats::VerdictKind::Negligible;
  }
  const std::string margin = num(kSmallestAucDifference, "%g") + " AUC";
  if (gains == methods.size()) return verdict(true);
  if (losses == methods.size()) return std::string(verdict(false)) + " (" + f.worse + " better, for both methods)";
  if (equal == methods.size()) return std::string(verdict(false)) + " (equal within +-" + margin + ", both methods)";
  if (losses + equal == methods.size())
    return std::string(verdict(false)) + " (" + f.worse + " better or equal within +-" + margin + ", each method)";
  return "**not shown** (neither the difference nor an equality within +-" + num(kSmallestAucDifference, "%g") +
         " AUC is shown for both methods)";
}

// The four verdicts of one truth (two findings, two methods), one Holm family, and each finding's verdict.
void findingsUnder(std::ostringstream& o, const json& rows, const char* truth, std::vector<std::string>& findings) {
  std::vector<DatasetComparison> c;
  for (const GroupFinding& f : kFindings)
    for (const char* method : kMethods) c.push_back(pairedGroups(rows, truth, method, f));
  std::vector<DatasetComparison*> family;
  for (DatasetComparison& comparison : c) family.push_back(&comparison);
  const std::string truth_name = truth ? truth : "the run's";
  decideFamily(family, "the 4 verdicts of this section under " + truth_name + " truth", groupOptions(),
               "pairs of data sets", "AUC");
  for (std::size_t i = 0; i < c.size(); ++i) {
    const GroupFinding& f = kFindings[i / 2];
    o << "| " << f.better << " - " << f.worse << " | " << truth_name << " | " << kMethods[i % 2] << " | "
      << c[i].per_dataset.size() << " | " << c[i].verdict.text << " | " << c[i].verdict.basis << " |\n";
    if (i % 2)
      findings.push_back(std::string("- ") + f.better + " better than " + f.worse + ", " + truth_name + " truth: " +
                         findingVerdict({&c[i - 1], &c[i]}, f) + ".");
  }
}

}  // namespace

void groupFindingsSection(std::ostringstream& o, const json& rows) {
  o << "Tested over pairs of data sets that differ only in the attribute (the same layout and the other attribute), "
    << "each data set's mean best AUC over its sets, the data set being the unit (docs/statistics.md, \"Verdicts\"): "
    << "a difference when the exact paired test rejects at alpha 0.05 after Holm's correction over the 4 verdicts "
    << "of one truth (one family per truth), an equality when the sign test puts the median, and the 95 % BCa "
    << "interval the mean, within +-" << num(kSmallestAucDifference, "%g") << " AUC; a finding holds when both "
    << "methods show it, and is **not shown** when the data show neither it nor its opposite or an equality.\n\n"
    << "| difference | truth | method | pairs | verdict | basis |\n|---|---|---|---|---|---|\n";
  std::vector<std::string> findings;
  if (!rows.empty() && rows.front().contains("truths"))
    for (const char* truth : {"full", "observable"}) findingsUnder(o, rows, truth, findings);
  else
    findingsUnder(o, rows, nullptr, findings);
  o << '\n';
  for (const std::string& line : findings) o << line << '\n';
  o << '\n';
}

}  // namespace occsweep::reproduce
