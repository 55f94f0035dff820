// report.md section 4: the paper's texture and environment findings, tested over pairs of data sets that differ only
// in that attribute (the same layout and the other attribute), one value per scene or pair of scenes, by the rules
// of docs/statistics.md ("Verdicts"): a difference needs the exact paired test to reject after Holm's correction, an equality needs the
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

// Each data set in `group`: the mean best AUC of `method` over its sets and its scene (the row's `scene`, its name in
// an older comparison.json), keyed by the data set's name with the group taken out: the key its partner in the
// other group has.
struct GroupMean {
  double auc = 0;  // the sum over the data set's sets until groupMeans divides it
  int sets = 0;
  std::string scene;
};
std::map<std::string, GroupMean> groupMeans(const json& rows, const char* truth, const char* method,
                                            const char* attribute, const std::string& group) {
  std::map<std::string, GroupMean> means;
  for (const json& r : rows) {
    const json& side = truth ? r.at("truths").at(truth) : r;
    if (r.at(attribute) != group || side.at(method).is_null()) continue;
    std::string key = r.at("dataset").get<std::string>();
    const std::string scene = r.value("scene", key);
    if (const auto at = key.find(group); at != std::string::npos) key.erase(at, group.size());
    GroupMean& m = means[key];
    m.auc += get(side.at(method).at("auc")), ++m.sets, m.scene = scene;
  }
  for (auto& [key, m] : means) m.auc /= m.sets;
  return means;
}

// The bootstrap and rules of compare, with the smallest AUC difference of interest.
CompareStatisticsOptions groupOptions() {
  CompareStatisticsOptions options;
  options.rules.smallest_effect = kSmallestAucDifference;
  return options;
}

// better - worse over the pairs of data sets that differ only in the finding's attribute, one value per pair of
// scenes (docs/statistics.md, "Verdicts", rule 1): a Voronoi data set and its plain twin are one scene, the unit of
// the texture finding; a building and its parking twin are two, and the pair's two textures are averaged into one
// value of the environment finding.
DatasetComparison pairedGroups(const json& rows, const char* truth, const char* method, const GroupFinding& f) {
  const auto better = groupMeans(rows, truth, method, f.attribute, f.better),
             worse = groupMeans(rows, truth, method, f.attribute, f.worse);
  std::map<std::string, std::pair<double, int>> by_unit;
  bool within_scene = true;
  for (const auto& [key, b] : better)
    if (const auto w = worse.find(key); w != worse.end()) {
      within_scene = within_scene && b.scene == w->second.scene;
      auto& [sum, n] = by_unit[b.scene == w->second.scene ? b.scene : b.scene + " - " + w->second.scene];
      sum += b.auc - w->second.auc, ++n;
    }
  std::vector<std::string> units;
  std::vector<double> differences;
  for (const auto& [unit, s] : by_unit) units.push_back(unit), differences.push_back(s.first / s.second);
  DatasetComparison c = pairedComparison(std::move(units), std::move(differences), groupOptions());
  c.unit_name = within_scene ? "scenes" : "pairs of scenes";
  return c;
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
  decideFamily(family, "the 4 verdicts of this section under " + truth_name + " truth", groupOptions(), nullptr,
               "AUC");
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
    << "each data set's mean best AUC over its sets, with the scene as the unit (docs/statistics.md, \"Verdicts\"): "
    << "a data set and its twin of the other texture are one scene, so the texture finding has one value per scene, "
    << "and the environment finding one per pair of scenes (building and parking of one layout, both textures "
    << "averaged); "
    << "a difference when the exact paired test rejects at alpha 0.05 after Holm's correction over the 4 verdicts "
    << "of one truth (one family per truth), an equality when the sign test puts the median, and the 95 % BCa "
    << "interval the mean, within +-" << num(kSmallestAucDifference, "%g") << " AUC; a finding holds when both "
    << "methods show it, and is **not shown** when the data show neither it nor its opposite or an equality.\n\n"
    << "| difference | truth | method | units | verdict | basis |\n|---|---|---|---|---|---|\n";
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
