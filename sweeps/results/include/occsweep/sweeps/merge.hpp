// Merging shards, and the best-AUC comparison behind the paper's Fig. 5.
#pragma once

#include <cmath>
#include <filesystem>
#include <map>
#include <optional>
#include <vector>

#include "occsweep/sweeps/results.hpp"

namespace occsweep {

/// Merges the shards of one sweep. Refuses (std::runtime_error naming the file) an incomplete file, a file of
/// another grid, data set, group or map setting, a duplicated combination, a combination outside the selection
/// and a missing one. When the grid file is found and its hash matches, every id's parameters are checked too.
/// Inputs of either format (results_store.hpp) are read map by map.
[[nodiscard]] ResultsFile mergeResults(const std::vector<std::filesystem::path>& files);
/// The same written to `out` atomically in the format its name asks for; into a store, map by map (memory: a bit
/// per combination of the grid and the grid's enumeration, not the results). Returns the number of maps.
std::uint64_t mergeResultsInto(const std::vector<std::filesystem::path>& files, const std::filesystem::path& out);

/// The ids a results file covers, checked against its selection by the caller.
[[nodiscard]] std::vector<std::uint64_t> coveredIds(const ResultsFile& f);

/// Checks one file's ids and parameters against its grid, when the grid file is found (returns false if not).
bool checkAgainstGrid(const ResultsFile& f, const std::string& file);

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
  std::optional<BestMap> octomap, knn;
  std::vector<std::size_t> octomap_files, knn_files;  ///< indices of the files of each method given for this row
  /// Every other method's best (the baselines of docs/methods.md), by method name.
  std::map<std::string, BestMap> others;
  [[nodiscard]] double improvementPercent() const;  ///< (knn - octomap) / octomap * 100; NaN if one is missing
  /// (method - baseline) / baseline * 100 for any two methods of the row; NaN if either is missing or the
  /// baseline's AUC is not above 0.
  [[nodiscard]] double improvementPercent(const std::string& method, const std::string& baseline = "octomap") const;
  /// The best map of any method (octomap, knn or one of `others`); none when this row has none.
  [[nodiscard]] std::optional<BestMap> best(const std::string& method) const;
};

/// The methods of `others` over all rows, by name: the columns compare adds after OctoMap and k-NN.
[[nodiscard]] std::vector<std::string> otherMethods(const std::vector<ComparisonRow>& rows);

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

/// Why a row has no number for a method (OctoMap when `knn` is false): no file of it given (or only for a data set
/// of the same name with other contents), or no AUC because the data set has no ground truth. Empty when it has one.
[[nodiscard]] std::string missingReason(const ComparisonRow& row, bool knn, const std::vector<ResultsFile>& files,
                                        const std::vector<std::string>& names);

}  // namespace occsweep
