// report.md: the paper's trend (Fig. 5: the improvement grows as OctoMap's AUC falls) with its controls. A Pearson r
// over all sets can come from the groups alone (Simpson's paradox: plain and Voronoi sets differ in both AUC and
// gain), so the trend is judged on the rank correlation, its permutation p-value and its sign within each texture
// (docs/statistics.md, "Correlation").
#include <cmath>
#include <stdexcept>

#include "occsweep/stats/correlation.hpp"
#include "reproduce_internal.hpp"

namespace occsweep::reproduce {
using nlohmann::json;

namespace {

constexpr std::size_t kPermutations = 10000;  // the report's text says 10,000
constexpr std::uint64_t kPermutationSeed = 1;
constexpr double kLevel = 0.05;

/// The permutation p-value, or NaN when no test is possible (fewer than 3 sets, or constant values).
double permutationP(const TrendInput& in, stats::CorrelationKind kind) {
  if (in.improvement.size() < 3) return NAN;
  try {
    return stats::correlationPermutationTest(in.octomap_auc, in.improvement, {kind, kPermutations, kPermutationSeed})
        .p_value;
  } catch (const std::invalid_argument&) {
    return NAN;
  }
}

std::vector<stats::GroupCorrelation> within(const TrendInput& in, const std::vector<std::string>& labels) {
  return stats::correlationWithinGroups(in.octomap_auc, in.improvement, labels);
}

}  // namespace

TrendInput trendInput(const json& rows, const char* truth) {
  TrendInput in;
  for (const auto& r : rows) {
    const json& side = truth ? r.at("truths").at(truth) : r;
    const double om = side.at("octomap").is_null() ? NAN : get(side.at("octomap").at("auc"));
    const double imp = get(side.at("improvement_percent"));
    if (!std::isfinite(om) || !std::isfinite(imp)) continue;
    in.octomap_auc.push_back(om);
    in.improvement.push_back(imp);
    in.texture.push_back(r.at("texture").get<std::string>());
    in.environment.push_back(r.at("environment").get<std::string>());
  }
  return in;
}

TrendControls trendControls(const TrendInput& in) {
  TrendControls c;
  c.sets = in.improvement.size();
  if (c.sets < 2) return c;
  c.pearson = stats::pearsonCorrelation(in.octomap_auc, in.improvement);
  c.spearman = stats::spearmanCorrelation(in.octomap_auc, in.improvement);
  c.pearson_p = permutationP(in, stats::CorrelationKind::Pearson);
  c.spearman_p = permutationP(in, stats::CorrelationKind::Spearman);
  c.by_texture = within(in, in.texture);
  c.pooled_within_texture = stats::pooledWithinGroupPearson(in.octomap_auc, in.improvement, in.texture);
  c.by_environment = within(in, in.environment);
  return c;
}

std::string trendVerdict(const TrendControls& c) {
  std::vector<std::string> fails;
  if (!(c.spearman < 0) || !(c.spearman_p < kLevel))
    fails.push_back("no trend: rank correlation " + num(c.spearman, "%+.3f") + ", p = " + num(c.spearman_p, "%.2g"));
  for (const auto& g : c.by_texture)
    if (!(g.spearman < 0)) fails.push_back("rho " + num(g.spearman, "%+.3f") + " within " + g.group + " sets");
  if (fails.empty()) return verdict(true);
  std::string s = std::string(verdict(false)) + " (";
  for (std::size_t i = 0; i < fails.size(); ++i) s += (i ? "; " : "") + fails[i];
  return s + ")";
}

std::string groupCorrelations(const std::vector<stats::GroupCorrelation>& groups) {
  std::string s;
  for (const auto& g : groups)
    s += (s.empty() ? "" : ", ") + g.group + " (" + std::to_string(g.n) + ") " + num(g.pearson, "%+.3f") + " / " +
         num(g.spearman, "%+.3f");
  return s.empty() ? "n/a" : s;
}

void trendParagraph(std::ostringstream& o, const TrendControls& c) {
  o << "The paper's trend, tested on the " << c.sets << " sets (improvement against OctoMap's best AUC; "
    << "two-sided permutation tests of |r| with y permuted against x, 10,000 random permutations, seed "
    << kPermutationSeed << ", all n! of them up to 8 sets; docs/statistics.md, "
    << "\"Correlation\"):\n\n"
    << "| sets | Pearson r | permutation p | Spearman rho | permutation p |\n|---|---|---|---|---|\n"
    << "| all " << c.sets << " | " << num(c.pearson, "%+.3f") << " | " << num(c.pearson_p, "%.2g") << " | "
    << num(c.spearman, "%+.3f") << " | " << num(c.spearman_p, "%.2g") << " |\n";
  for (const auto& [kind, groups] : {std::pair{"texture", &c.by_texture}, {"environment", &c.by_environment}})
    for (const auto& g : *groups)
      o << "| " << kind << ' ' << g.group << " (" << g.n << ") | " << num(g.pearson, "%+.3f") << " | | "
        << num(g.spearman, "%+.3f") << " | |\n";
  o << "| pooled within the textures | " << num(c.pooled_within_texture, "%+.3f") << " | | | |\n"
    << "\nThe trend holds when the rank correlation is negative with permutation p < " << kLevel
    << " and negative within each texture (a correlation over all sets alone can come from the differences "
    << "between the groups): " << trendVerdict(c) << ".\n\n";
}

}  // namespace occsweep::reproduce
