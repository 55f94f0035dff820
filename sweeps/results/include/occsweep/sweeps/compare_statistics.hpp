// Whether a method's gain over a baseline is real (docs/statistics.md): the verdict over scenes (the unit of the
// tests: data sets that share a recording or a scene, compare_units.hpp) by the rules of "Verdicts", of the per-set
// optima and cross-validated by scene; the per-set interval, tests and effect size as description; per method, its
// cross-validated scores and its budget curve (the expected best of n maps of its grid), so a bigger grid is not
// mistaken for a better method.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "occsweep/sweeps/baseline.hpp"
#include "occsweep/stats/bootstrap.hpp"
#include "occsweep/stats/effect_size.hpp"
#include "occsweep/stats/sign_test.hpp"
#include "occsweep/stats/verdict.hpp"
#include "occsweep/stats/wilcoxon.hpp"
#include "occsweep/sweeps/compare.hpp"
#include "occsweep/sweeps/compare_units.hpp"

namespace occsweep {

struct CompareStatisticsOptions {
  std::string baseline = kDefaultBaseline;  ///< every other method is compared with this one
  double level = 0.95;               ///< of the bootstrap interval
  std::size_t resamples = 10000;     ///< bootstrap resamples (BCa)
  std::uint64_t seed = 1;            ///< bootstrap seed: the same files give the same interval
  std::size_t budget_max_maps = 20000;  ///< budget curves cost O(maps^2) per set: none for larger grids
  stats::VerdictRules rules;         ///< alpha (after Holm) and the smallest effect of interest, in percent
  UnitRule units = UnitRule::Provenance;  ///< what one unit of the tests is (`compare --units`)
};

/// The default options against `baseline`.
[[nodiscard]] inline CompareStatisticsOptions statisticsAgainst(std::string baseline) {
  CompareStatisticsOptions options;
  options.baseline = std::move(baseline);
  return options;
}

/// How a method's optimum holds up when its parameters are chosen elsewhere (stats::leaveOneGroupOut): the mean
/// per-set optimum, the mean score of the parameters chosen on the other groups, and their gap (overfitting).
struct CrossValidated {
  std::size_t groups = 0;  ///< 0: not computed (fewer than 2 groups, grids that differ, or an undefined AUC)
  double optimum = 0.0, score = 0.0, gap = 0.0;
};

/// What the budget curves say against the baseline: the mean over sets of the expected best AUC of `budget` maps
/// (the baseline grid's size), and the smallest budget whose mean expected best passes the baseline's mean best.
struct BudgetSummary {
  std::size_t maps = 0;                    ///< maps in the method's grid (0: not computed)
  std::size_t budget = 0;                  ///< the baseline grid's maps
  double expected_best_at_budget = 0.0;    ///< mean over sets
  std::optional<std::size_t> first_above_baseline;  ///< none: never, even with the whole grid
};

/// One comparison with the baseline whose unit is the scene, or the data set (docs/statistics.md, "Verdicts"): each
/// unit's improvement in percent of the baseline's AUC (the mean over its sets, which share a scene), their
/// bootstrap interval, the exact paired test, its p-value after Holm's correction over the methods compared with
/// the baseline, and the verdict these give.
struct DatasetComparison {
  std::vector<std::string> datasets;  ///< the units' names (SampleUnits::of_row), in the order of per_dataset
  std::vector<double> per_dataset;  ///< improvement %, one per unit
  std::optional<stats::BootstrapInterval> interval;  ///< none below 2 data sets
  std::optional<stats::ExactPairedTest> test;        ///< none when every data set's difference is 0
  double holm_p = 1.0;
  std::size_t family = 0;           ///< the comparisons Holm's correction ran over
  std::string holm_family;          ///< which verdicts were corrected together, in words (holmFamilyText)
  std::string not_computed;         ///< why there is no evidence (then the verdict says so); empty when there is
  std::string unit_name = "data sets";  ///< what one value is: "scenes" where provenance grouped data sets
  std::string sample;               ///< "20 data sets over 10 scenes (how the units were found)": in the basis
  stats::Verdict verdict;
};

/// One method over the sets where it and the baseline both have an AUC.
struct MethodStatistics {
  std::string method;
  bool is_baseline = false;
  std::size_t sets = 0;              ///< sets with an AUC of this method (and, but for the baseline, of the baseline)
  std::size_t datasets = 0;          ///< the data sets those sets belong to
  std::size_t scenes = 0;            ///< the units of the tests those data sets form (compare_units.hpp)
  double mean_best_auc = 0.0;        ///< mean per-set optimum (the paper's number)
  CrossValidated leave_one_set_out, leave_one_dataset_out;
  BudgetSummary budget;
  // Against the baseline (not for the baseline itself); differences are method - baseline on each set.
  std::size_t better = 0, worse = 0, ties = 0;
  /// Sets where any of the method's results (every file given for the set) holds a map that scores the baseline's
  /// best AUC exactly (anchored and observed AUC equal to the last bit), found from the maps: there the method's
  /// optimum is at least the baseline's (knn-opt's maps with p_u = p_l often score as OctoMap's; docs/statistics.md,
  /// "Grids that nest"); only `better` sets are strict gains.
  std::size_t sets_holding_baseline_best = 0;
  /// Units (scenes, or data sets) every set of which holds the baseline's best: no evidence about the method.
  std::size_t scenes_holding_baseline_best = 0;
  /// The optima comparison over the units that do not nest, on which the optima verdict is decided (in the same
  /// Holm family); none when no unit nests. `optima` keeps every unit as description (its Holm p over the family of
  /// every method's units), and the verdict that says which units it rests on.
  std::optional<DatasetComparison> optima_not_nested;
  // Description over point cloud sets (not independent: sets of one data set share a scene).
  std::optional<stats::BootstrapInterval> improvement_percent;  ///< mean of (m - b) / b * 100; none below 2 sets
  std::optional<stats::SignedRankResult> wilcoxon;              ///< of the AUC differences; none when all are zero
  std::optional<stats::SignTestResult> sign;
  std::optional<stats::PairedEffectSize> effect;
  /// The method's leave-one-set-out score against the baseline's, per set, in percent: optimistic, as the
  /// parameters are chosen partly on sibling sets of the held-out set's data set; none when not computable.
  std::optional<stats::BootstrapInterval> leave_one_set_out_improvement;
  /// The verdicts: over the per-set optima, and cross-validated (each data set held out in turn, parameters
  /// chosen on the other data sets).
  DatasetComparison optima, cross_validated;
};

/// The mean over sets of a method's budget curve: entry n-1 is the expected best AUC of n maps of its grid drawn at
/// random (stats::expectedBestCurve). Empty when its sets do not share one grid, an AUC is undefined, or the grid
/// has more than `max_maps` maps.
[[nodiscard]] std::vector<double> meanBudgetCurve(const std::vector<ComparisonRow>& rows,
                                                  const std::vector<ResultsFile>& files, const std::string& method,
                                                  std::size_t max_maps = CompareStatisticsOptions{}.budget_max_maps);

/// Data sets the statistics pool by name from rows of several contents: a name without a DATASET/pcs-NNNN set part
/// shared by rows of different contents, or given both alone and with sets (docs/statistics.md, "Verdicts"), among
/// the rows whose unit their name decides under `rule`; compare notes them.
[[nodiscard]] std::vector<std::string> pooledDatasetNames(const std::vector<ComparisonRow>& rows,
                                                        UnitRule rule = UnitRule::Provenance);

/// One paired comparison over units named `names` (data sets, or pairs of them): the values, their interval and the
/// exact test, with its verdict left to decideFamily.
[[nodiscard]] DatasetComparison pairedComparison(std::vector<std::string> names, std::vector<double> values,
                                                 const CompareStatisticsOptions& options);

/// Holm's correction over `family`, then each comparison's verdict by options.rules (docs/statistics.md,
/// "Verdicts"), its units and values named `unit_name` (null: each comparison's own `unit_name`) and `value_unit`;
/// `family_text` says which verdicts these are.
void decideFamily(const std::vector<DatasetComparison*>& family, const std::string& family_text,
                  const CompareStatisticsOptions& options, const char* unit_name, const char* value_unit);

/// The Holm family of one kind of verdict ("optima", "cross-validated") in words: "the 4 optima verdicts of knn,
/// ror-octomap, ... against octomap", or for one method "the optima verdict of knn against octomap alone (no
/// correction)". Every output of compare and report.md states it (docs/statistics.md, "Verdicts").
[[nodiscard]] std::string holmFamilyText(const std::string& kind, const std::vector<std::string>& methods,
                                         const std::string& baseline);

/// Every method's statistics, the baseline's first. Throws std::invalid_argument naming the baseline and the
/// methods given when no file of the baseline was given.
[[nodiscard]] std::vector<MethodStatistics> compareStatistics(const std::vector<ComparisonRow>& rows,
                                                              const std::vector<ResultsFile>& files,
                                                              const CompareStatisticsOptions& options = {});

/// The statistics as JSON (`compare --json`'s "statistics", reproduce's comparison.json), with the options that
/// made the intervals.
[[nodiscard]] nlohmann::json toJson(const std::vector<MethodStatistics>& statistics,
                                    const CompareStatisticsOptions& options);

}  // namespace occsweep
