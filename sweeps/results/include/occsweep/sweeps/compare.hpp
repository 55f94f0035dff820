// The best-AUC comparison of methods behind the paper's Fig. 5: each data set's best map of each method, and why
// a set of results files cannot be compared as it is (docs/statistics.md).
#pragma once

#include <cmath>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "occsweep/sweeps/results.hpp"

namespace occsweep {

struct BestMap {
  double auc = 0.0;       ///< anchored AUC (docs/definitions.md, Confusion counts and AUC)
  double observed = 0.0;  ///< AUC over the observed span
  MapParams params;
  std::uint64_t map_index = 0;
  std::size_t file = 0;  ///< index of the results file it comes from, in compareBest's input
};

/// One data set and point cloud set: the best map of each method.
struct ComparisonRow {
  std::string dataset, point_cloud_set, dataset_hash;
  /// What the data set was made from (its source's `provenance`, docs/dataset-format.md); null when not recorded.
  nlohmann::json provenance;
  /// Each method's best map, by method name; a method whose files hold no AUC has none.
  std::map<std::string, BestMap> best_of;
  /// Each method's files given for this row (indices into compareBest's input), by method name.
  std::map<std::string, std::vector<std::size_t>> files_of;
  /// (method - baseline) / baseline * 100 for any two methods of the row; NaN if either is missing or the
  /// baseline's AUC is not above 0.
  [[nodiscard]] double improvementPercent(const std::string& method, const std::string& baseline) const;
  /// The best map of a method; none when this row has none.
  [[nodiscard]] std::optional<BestMap> best(const std::string& method) const;
};

/// Every method with a best map in some row, by name.
[[nodiscard]] std::vector<std::string> comparedMethods(const std::vector<ComparisonRow>& rows);

/// Whether a map of AUC `auc` takes the best place from `best` (none yet): the highest AUC, NaN never, ties to the
/// map seen first (the lowest map index: stable across runs).
[[nodiscard]] inline bool isBetterBest(double auc, std::optional<double> best) {
  return !std::isnan(auc) && (!best || auc > *best);
}

[[nodiscard]] std::vector<ComparisonRow> compareBest(const std::vector<ResultsFile>& files);

/// When `files` (named by `names`) count different truths (full and observable, docs/results-format.md "Truth"):
/// a sentence naming the first file of each and the field map.truth; empty when they all count the same truth.
/// Their AUCs measure different things, so compare refuses them even with --allow-mixed.
[[nodiscard]] std::string mixedTruths(const std::vector<ResultsFile>& files, const std::vector<std::string>& names);

/// Why `files` (named by `names`) cannot be compared as they are, one sentence each naming the files: a shard
/// instead of a whole grid or Eq. 16 group, another resolution or s_c within a data set, another k-NN variant or
/// statistics mode, two results of one method for one data set (or one file given twice). Empty when comparable.
/// (Rows are data-set contents, by hash: files of one name with other scans, region or truth are never compared with
/// each other; missingReason says so.)
[[nodiscard]] std::vector<std::string> mixedSettings(const std::vector<ResultsFile>& files,
                                                     const std::vector<std::string>& names);

/// Why a row has no number for `method`: no file of it given (or only for a data set of the same name with other
/// contents), or no AUC because the data set has no ground truth. Empty when it has one.
[[nodiscard]] std::string missingReason(const ComparisonRow& row, const std::string& method,
                                        const std::vector<ResultsFile>& files, const std::vector<std::string>& names);

}  // namespace occsweep
