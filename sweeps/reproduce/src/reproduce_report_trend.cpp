// report.md: the paper's trend (Fig. 5: the improvement grows as OctoMap's AUC falls) with its controls. A Pearson r
// over all sets can come from the groups alone (Simpson's paradox: plain and Voronoi sets differ in both AUC and
// gain), so the trend is judged on the rank correlation, its permutation p-value and its sign within each texture
// (docs/statistics.md, "Correlation").
#include <array>
#include <cmath>
#include <map>
#include <stdexcept>

#include "occsweep/stats/correlation.hpp"
#include "reproduce_internal.hpp"

namespace occsweep::reproduce {
using nlohmann::json;

namespace {

constexpr std::size_t kPermutations = 10000;  // the report's text says 10,000
constexpr std::uint64_t kPermutationSeed = 1;
constexpr double kLevel = 0.05;

/// The permutation p-value of y against x, or NaN when no test is possible (fewer than 3 pairs, or constant values).
double permutationP(const std::vector<double>& x, const std::vector<double>& y, stats::CorrelationKind kind) {
  if (y.size() < 3) return NAN;
  try {
    return stats::correlationPermutationTest(x, y, {kind, kPermutations, kPermutationSeed}).p_value;
  } catch (const std::invalid_argument&) {
    return NAN;
  }
}

double permutationP(const TrendInput& in, stats::CorrelationKind kind) {
  return permutationP(in.octomap_auc, in.improvement, kind);
}

/// Each unit's mean OctoMap AUC and mean improvement over its sets, and its texture, in order of first appearance.
struct UnitMeans {
  std::vector<double> auc, improvement;
  std::vector<std::string> texture;
};

UnitMeans meansBy(const TrendInput& in, const std::vector<std::string>& unit) {
  std::vector<std::size_t> first;  // each unit's first set
  std::map<std::string, std::array<double, 3>> sums;  // AUC, improvement, sets
  for (std::size_t i = 0; i < in.improvement.size(); ++i) {
    auto [it, added] = sums.try_emplace(unit[i], std::array<double, 3>{0, 0, 0});
    if (added) first.push_back(i);
    it->second[0] += in.octomap_auc[i], it->second[1] += in.improvement[i], it->second[2] += 1;
  }
  UnitMeans means;
  for (const std::size_t i : first) {
    const auto& s = sums.at(unit[i]);
    means.auc.push_back(s[0] / s[2]), means.improvement.push_back(s[1] / s[2]), means.texture.push_back(in.texture[i]);
  }
  return means;
}

/// Spearman's rho within each texture over its scenes' means (each scene's data set of that texture), and its
/// permutation p.
void withinTexturesOverScenes(const TrendInput& in, TrendControls& c) {
  std::vector<std::string> scene_in_texture;
  for (std::size_t i = 0; i < in.scene.size(); ++i) scene_in_texture.push_back(in.scene[i] + '\n' + in.texture[i]);
  const UnitMeans m = meansBy(in, scene_in_texture);
  c.by_texture_scenes = stats::correlationWithinGroups(m.auc, m.improvement, m.texture);
  for (const auto& g : c.by_texture_scenes) {
    std::vector<double> auc, improvement;
    for (std::size_t i = 0; i < m.texture.size(); ++i)
      if (m.texture[i] == g.group) auc.push_back(m.auc[i]), improvement.push_back(m.improvement[i]);
    c.by_texture_scenes_p.push_back(permutationP(auc, improvement, stats::CorrelationKind::Spearman));
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
    in.scene.push_back(r.value("scene", r.at("dataset").get<std::string>()));
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
  const UnitMeans means = meansBy(in, in.scene);
  c.scenes = means.auc.size();
  if (c.scenes >= 2) c.scene_spearman = stats::spearmanCorrelation(means.auc, means.improvement);
  c.scene_spearman_p = permutationP(means.auc, means.improvement, stats::CorrelationKind::Spearman);
  withinTexturesOverScenes(in, c);
  return c;
}

std::string trendVerdict(const TrendControls& c) {
  std::vector<std::string> fails;
  auto check = [&](const std::string& where, double rho, double p) {
    if (!(rho < 0) || !(p < kLevel)) fails.push_back(where + ": rho " + num(rho, "%+.3f") + ", p = " + num(p, "%.2g"));
  };
  check("over the " + std::to_string(c.scenes) + " scenes", c.scene_spearman, c.scene_spearman_p);
  for (std::size_t i = 0; i < c.by_texture_scenes.size(); ++i) {
    const auto& g = c.by_texture_scenes[i];
    check("within the " + std::to_string(g.n) + " " + g.group + " scenes", g.spearman, c.by_texture_scenes_p[i]);
  }
  if (fails.empty()) return verdict(true);
  std::string s = "**not shown** (";
  for (std::size_t i = 0; i < fails.size(); ++i) s += (i ? "; " : "") + fails[i];
  return s + ")";
}

std::string textureCorrelationsOverScenes(const TrendControls& c) {
  std::string s;
  for (std::size_t i = 0; i < c.by_texture_scenes.size(); ++i) {
    const auto& g = c.by_texture_scenes[i];
    s += (s.empty() ? "" : ", ") + g.group + " (" + std::to_string(g.n) + ") " + num(g.spearman, "%+.3f") + " (" +
         num(c.by_texture_scenes_p[i], "%.2g") + ")";
  }
  return s.empty() ? "n/a" : s;
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
    << num(c.spearman, "%+.3f") << " | " << num(c.spearman_p, "%.2g") << " |\n"
    << "| scene means (" << c.scenes << ") | | | " << num(c.scene_spearman, "%+.3f") << " | "
    << num(c.scene_spearman_p, "%.2g") << " |\n";
  for (std::size_t i = 0; i < c.by_texture_scenes.size(); ++i)
    o << "| texture " << c.by_texture_scenes[i].group << ", scene means (" << c.by_texture_scenes[i].n << ") | | | "
      << num(c.by_texture_scenes[i].spearman, "%+.3f") << " | " << num(c.by_texture_scenes_p[i], "%.2g") << " |\n";
  for (const auto& [kind, groups] : {std::pair{"texture", &c.by_texture}, {"environment", &c.by_environment}})
    for (const auto& g : *groups)
      o << "| " << kind << ' ' << g.group << " (" << g.n << ") | " << num(g.pearson, "%+.3f") << " | | "
        << num(g.spearman, "%+.3f") << " | |\n";
  o << "| pooled within the textures | " << num(c.pooled_within_texture, "%+.3f") << " | | | |\n"
    << "\n" << kTrendRule << ". Here: " << trendVerdict(c) << ".\n\n";
}

}  // namespace occsweep::reproduce
