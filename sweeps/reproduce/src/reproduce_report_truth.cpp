// report.md: the Fig. 5 comparison under full and observable truth side by side (docs/results-format.md,
// "Truth"). Both come from the same maps: only which truth voxels count differs.
#include <algorithm>
#include <cmath>
#include <map>

#include "reproduce_internal.hpp"

namespace occsweep::reproduce {
using nlohmann::json;

namespace {

constexpr const char* kTruths[2] = {"full", "observable"};

double auc(const json& side, const char* method) {
  return side.at(method).is_null() ? NAN : get(side.at(method).at("auc"));
}

// Means over the rows for one truth: best AUC of each method, improvement, and k-NN's wins.
struct TruthSummary {
  std::vector<double> om, knn, improvement;
  std::map<std::string, std::vector<double>> om_by, knn_by;  // by texture and by environment
};

/// The paper's trend under each truth, with the controls of section 3 (docs/statistics.md, "Correlation").
void trendByTruth(std::ostringstream& o, const json& rows) {
  o << "\nThe paper's trend under each truth (improvement against OctoMap's best AUC; permutation p of 10,000 "
    << "permutations, seed 1; r / rho within each group, its sets in brackets; pooled: r with each texture's means "
    << "removed; over scene means: rho within each texture over its scenes' means, its scenes and p in "
    << "brackets). " << kTrendRule << ".\n\n"
    << "| truth | Pearson r (p) | Spearman rho (p) | rho over scene means (p) | within texture over scene "
    << "means | within texture | within environment | trend |\n|---|---|---|---|---|---|---|---|\n";
  for (const char* truth : kTruths) {
    const TrendControls c = trendControls(trendInput(rows, truth));
    o << "| " << truth << " | " << num(c.pearson, "%+.3f") << " (" << num(c.pearson_p, "%.2g") << ") | "
      << num(c.spearman, "%+.3f") << " (" << num(c.spearman_p, "%.2g") << ") | "
      << num(c.scene_spearman, "%+.3f") << " (" << num(c.scene_spearman_p, "%.2g") << ") | "
      << textureCorrelationsOverScenes(c) << " | " << groupCorrelations(c.by_texture)
      << "; pooled " << num(c.pooled_within_texture, "%+.3f") << " | " << groupCorrelations(c.by_environment)
      << " | " << trendVerdict(c) << " |\n";
  }
  o << "\n";
}

}  // namespace

void truthSection(std::ostringstream& o, const json& comparison) {
  const json& rows = comparison.at("rows");
  if (rows.empty() || !rows.front().contains("truths")) return;  // a comparison.json of an older run
  o << "## 3b. Full against observable truth\n\n"
    << "The same maps, counted twice: full truth (every truth voxel of the region, the paper's and the default) and "
    << "observable truth (only truth voxels that a ray from a scan origin of the set, aimed at the voxel's centre or "
    << "at one of its face centres inside that scan's camera image, reaches within s_c before any other truth "
    << "voxel; the others, such as box "
    << "interiors, leave the evaluation: docs/results-format.md, "
    << "\"Truth\"). TPR ceiling: the highest TPR any combination of either grid reaches.\n\n"
    << "| data set | rank | true voxels full / obs. | OctoMap AUC full | obs. | k-NN AUC full | obs. "
    << "| improvement % full | obs. | TPR ceiling full | obs. |\n|---|---|---|---|---|---|---|---|---|---|---|\n";
  TruthSummary sum[2];
  for (const auto& r : rows) {
    const json& t = r.at("truths");
    o << "| " << r.at("dataset").get<std::string>() << " | " << r.at("rank_label").get<std::string>() << " | "
      << t.at("full").at("true_voxels").get<std::uint64_t>() << " / "
      << t.at("observable").at("true_voxels").get<std::uint64_t>() << " |";
    for (const char* column : {"octomap", "knn", "improvement_percent", "tpr_ceiling"})
      for (int i = 0; i < 2; ++i) {
        const json& side = t.at(kTruths[i]);
        const double v = column == std::string("improvement_percent") || column == std::string("tpr_ceiling")
                             ? get(side.at(column))
                             : auc(side, column);
        o << ' ' << num(v, column == std::string("improvement_percent") ? "%+.2f" : "%.4f") << " |";
      }
    o << "\n";
    for (int i = 0; i < 2; ++i) {
      const json& side = t.at(kTruths[i]);
      const double om = auc(side, "octomap"), knn = auc(side, "knn"), imp = get(side.at("improvement_percent"));
      TruthSummary& s = sum[i];
      if (std::isfinite(om)) s.om.push_back(om);
      if (std::isfinite(knn)) s.knn.push_back(knn);
      if (std::isfinite(imp)) s.improvement.push_back(imp);
      for (const char* key : {"texture", "environment"}) {
        if (std::isfinite(om)) s.om_by[r.at(key).get<std::string>()].push_back(om);
        if (std::isfinite(knn)) s.knn_by[r.at(key).get<std::string>()].push_back(knn);
      }
    }
  }
  o << "\n| truth | mean best OctoMap AUC | mean best k-NN AUC | mean improvement % | k-NN better | "
    << "improvement range % | voronoi / plain OctoMap AUC | building / parking OctoMap AUC |\n"
    << "|---|---|---|---|---|---|---|---|\n";
  for (int i = 0; i < 2; ++i) {
    const TruthSummary& s = sum[i];
    const auto better = std::count_if(s.improvement.begin(), s.improvement.end(), [](double v) { return v > 0; });
    const auto [lo, hi] = std::minmax_element(s.improvement.begin(), s.improvement.end());
    auto groupMean = [&](const char* g) {
      const auto it = s.om_by.find(g);
      return it == s.om_by.end() ? NAN : mean(it->second);
    };
    o << "| " << kTruths[i] << " | " << num(mean(s.om)) << " | " << num(mean(s.knn)) << " | "
      << num(mean(s.improvement), "%+.2f") << " | " << better << " of " << s.improvement.size() << " | "
      << (s.improvement.empty() ? std::string("n/a") : num(*lo, "%+.2f") + " to " + num(*hi, "%+.2f")) << " | "
      << num(groupMean("voronoi")) << " / " << num(groupMean("plain")) << " | " << num(groupMean("building"))
      << " / " << num(groupMean("parking")) << " |\n";
  }
  trendByTruth(o, rows);
}

}  // namespace occsweep::reproduce
