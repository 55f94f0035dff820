// Helpers shared by the reproduce steps (reproduce_*.cpp); not part of the public API.
#pragma once

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "occsweep/io/bounded_read.hpp"  // readJsonFile
#include "occsweep/stats/correlation.hpp"
#include "occsweep/sweeps/reproduce.hpp"
#include "occsweep/sweeps/results.hpp"
#include "occsweep/eval/json_input.hpp"

namespace occsweep::reproduce {

/// Runs (or resumes, or reuses when complete) one sweep of a point cloud set into OUT/sweeps/NAME/.
[[nodiscard]] ResultsFile sweepSet(const ReproduceConfig& c, const RankedDataset& d, std::size_t rank,
                                   const std::string& grid, const SweepSelection& selection = {});

/// The same sweep under full and observable truth (docs/results-format.md, "Truth"), both counted from the same
/// maps in one pass; the observable results go beside the full ones as NAME-observable.json.
struct BothTruths {
  ResultsFile full, observable;
};
/// `resolution`: the map's, metres; none: the sweep's default (0.1 m, Section 4.2).
[[nodiscard]] BothTruths sweepSetBothTruths(const ReproduceConfig& c, const RankedDataset& d, std::size_t rank,
                                            const std::string& grid, std::optional<double> resolution = std::nullopt);

/// The data set with this name, or the first one when it is not in the run (small runs pick a subset).
[[nodiscard]] const RankedDataset& datasetOrFirst(const std::vector<RankedDataset>& d, const std::string& name);

/// Index of a data set in paperDatasetNames() (its Eq. 16 group); the list position for other names.
[[nodiscard]] std::size_t paperIndex(const std::string& name, std::size_t fallback);


/// A number for report.md: `format` applied, "n/a" for NaN and infinities.
[[nodiscard]] inline std::string num(double v, const char* format = "%.4f") {
  if (!std::isfinite(v)) return "n/a";
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

/// A JSON number, or NaN for null (how the step files store NaN).
[[nodiscard]] inline double get(const nlohmann::json& j) { return j.is_number() ? j.get<double>() : NAN; }

/// A finding's verdict in report.md.
[[nodiscard]] inline const char* verdict(bool holds) { return holds ? "**holds**" : "**does not hold**"; }

/// Arithmetic mean; NaN for none.
[[nodiscard]] inline double mean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return v.empty() ? NAN : s / double(v.size());
}

/// report.md's sections 3 and 4 (Fig. 5): improvement and the texture / environment means.
void comparisonSection(std::ostringstream& o, const nlohmann::json& comparison);

/// report.md section 4's tests of the texture and environment findings over pairs of scenes.
void groupFindingsSection(std::ostringstream& o, const nlohmann::json& rows);

/// The paper's trend (Fig. 5) over the sets of comparison.json: OctoMap's best AUC against k-NN's improvement,
/// with each set's texture and environment; sets where either is undefined are left out.
struct TrendInput {
  std::vector<double> octomap_auc, improvement;
  std::vector<std::string> texture, environment;
  std::vector<std::string> scene;  ///< the row's `scene` (compare's unit); its data set in an older comparison.json
};
/// `truth` "full" or "observable" reads rows' `truths`; nullptr reads the rows' own fields (the run's truth).
[[nodiscard]] TrendInput trendInput(const nlohmann::json& rows, const char* truth);

/// The trend with its controls (docs/statistics.md, "Correlation"): Pearson r and Spearman rho with permutation
/// p-values (10,000 permutations, seed 1), both within each texture and each environment, the pooled
/// within-texture r (each texture's means removed), and the rank correlation over the scenes' means, the unit of
/// the verdict: the sets of one scene (its data sets in both textures) share its geometry, so permuting sets or
/// data sets treats them as independent.
struct TrendControls {
  std::size_t sets = 0, scenes = 0;
  double pearson = NAN, spearman = NAN, pearson_p = NAN, spearman_p = NAN, pooled_within_texture = NAN;
  double scene_spearman = NAN, scene_spearman_p = NAN;
  std::vector<stats::GroupCorrelation> by_texture, by_environment;  ///< over sets: description
  /// Within each texture over its scenes' means (one data set each), the unit the verdict uses throughout, with
  /// permutation p.
  std::vector<stats::GroupCorrelation> by_texture_scenes;
  std::vector<double> by_texture_scenes_p;
};
[[nodiscard]] TrendControls trendControls(const TrendInput& in);

/// The trend's rule in report.md's words (docs/statistics.md, "Correlation").
inline constexpr const char* kTrendRule =
    "The trend is shown (**holds**) when Spearman's rho over the scenes' means, the verdicts' unit (the sets of one "
    "scene, in both textures, share its geometry: permuting sets or data sets as if independent makes the p-values "
    "liberal), is negative with permutation p < 0.05 both over all scenes and within each texture's scenes (a "
    "correlation over all alone can come from the differences between the groups); all must reject (an intersection-union test, so no "
    "correction). Otherwise it is **not shown**: these data cannot show the trend, which is not evidence that there "
    "is none";

/// "**holds**" by kTrendRule, else "**not shown** (what fails)".
[[nodiscard]] std::string trendVerdict(const TrendControls& c);

/// "plain (10) -0.079 (0.84), ...": each texture's scenes, rho over their means and its permutation p.
[[nodiscard]] std::string textureCorrelationsOverScenes(const TrendControls& c);

/// "plain (30) +0.215 / +0.190, ...": each group's n, Pearson r and Spearman rho.
[[nodiscard]] std::string groupCorrelations(const std::vector<stats::GroupCorrelation>& groups);

/// report.md section 3's table of the trend's controls and its verdict.
void trendParagraph(std::ostringstream& o, const TrendControls& c);

/// report.md's section on the same comparison under full and observable truth, side by side.
void truthSection(std::ostringstream& o, const nlohmann::json& comparison);

/// report.md's section on k-NN against the baselines of docs/methods.md (sor-octomap, ror-octomap, range-octomap).
void baselineSection(std::ostringstream& o, const nlohmann::json& comparison);

/// report.md's section on real stereo without the voxel filter (real-stereo.json).
void realStereoSection(std::ostringstream& o, const nlohmann::json& real_stereo);

/// report.md's "Is the gain real?": every method against the optimal OctoMap with intervals, tests, cross-validated
/// scores and budget curves (docs/statistics.md).
void gainSection(std::ostringstream& o, const nlohmann::json& comparison);

}  // namespace occsweep::reproduce
