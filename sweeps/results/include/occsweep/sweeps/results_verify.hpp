// What `results check` verifies beyond each field's type: everything a results file claims (docs/results-format.md).
#pragma once

#include <filesystem>
#include <memory>
#include <string>

#include "occsweep/sweeps/results.hpp"
#include "occsweep/sweeps/results_file.hpp"

namespace occsweep {

/// Largest TP+FP+FN+TN a map can have: the voxels of OctoMap's 16-bit key space, 65536^3 = 2^48.
inline constexpr std::uint64_t kMaxRegionVoxels = std::uint64_t(1) << 48;
/// Largest grid whose Eq. 16 group membership is checked (the permutation costs 8 bytes a combination: 128 MiB).
inline constexpr std::uint64_t kMaxCheckedPermutation = std::uint64_t(1) << 24;

/// Checks without the grid file (std::runtime_error naming the file, the field and the rule): sane settings
/// (resolution, s_c, variant, statistics mode, selection within the grid's combinations), probabilities in
/// [0, 1], every map index and every id at most once, thresholds in increasing p_t, every map of the file
/// counting the same region (one TP+FP+FN+TN, one TP+FN, at most 2^48 voxels), and for a complete whole grid
/// or Eq. 16 group exactly as many ids as the selection holds (and, for a group, its ids).
void verifyClaims(const ResultsFile& f, const std::string& file);

/// verifyClaims one map at a time, in the file's order: `results check` of a store of any size. Memory: the
/// Eq. 16 group's ids when the file is a complete group (at most kMaxCheckedPermutation), nothing else per map.
class ClaimsChecker {
 public:
  ClaimsChecker(const ResultsHeader& header, bool complete, const std::string& file);  ///< checks the settings
  ~ClaimsChecker();
  void add(const MapResult& m);
  void finish() const;  ///< a complete whole grid or group: every id of the selection seen

 private:
  struct State;
  std::unique_ptr<State> state_;
};

/// With the grid of the file (its file found, same hash), one map at a time in increasing index: each map is the
/// grid's with its parameters and p_t, and in a complete file every map of the selection, cut to the shard, is
/// there exactly once with exactly its thresholds, and no other. Memory: the grid's enumeration.
class GridChecker {
 public:
  GridChecker(const ResultsHeader& header, bool complete, const std::string& file);
  ~GridChecker();
  [[nodiscard]] bool found() const;  ///< false: the grid file is not found or has another hash (nothing checked)
  void add(const MapResult& m);
  void finish() const;
  struct State;

 private:
  std::unique_ptr<State> state_;
};

/// With the data set the file names (`results check --dataset DIR`), one map at a time: its content hash is the
/// file's, and every threshold counts the region's voxels at the file's resolution (TP+FP+FN+TN) and the truth's
/// voxels (TP+FN).
class DatasetChecker {
 public:
  DatasetChecker(const ResultsHeader& header, const std::string& file, const std::filesystem::path& dataset);
  ~DatasetChecker();
  void add(const MapResult& m);

 private:
  struct State;
  std::unique_ptr<State> state_;
};

void verifyAgainstDataset(const ResultsFile& f, const std::string& file, const std::filesystem::path& dataset);

/// What `results check` found: a complete, consistent file of either format, read map by map.
struct ResultsCheck {
  ResultsHeader header;
  std::uint64_t maps = 0, combinations = 0;
  bool grid_checked = false;  ///< the grid file was found with the same hash, and every map checked against it
};
/// Every claim of `file` (ClaimsChecker), against its grid when found (GridChecker) and against `dataset` when
/// not empty (DatasetChecker). Throws std::runtime_error naming the file for the first failure, and for an
/// incomplete file.
[[nodiscard]] ResultsCheck checkResultsFile(const std::filesystem::path& file, const std::filesystem::path& dataset);
/// checkResultsFile and the read in one: the file is opened once (a store through one connection, a JSON file read
/// once) and each map, once its own checks passed, goes to `visit`; `header` (when given) receives the header,
/// completeness, seconds and truth voxels. The checks of the whole file end it: use what `visit` kept only once this
/// returns. What is checked is what is read, even when the file is replaced at its name meanwhile
/// (docs/results-format.md, "Reading").
ResultsCheck readCheckedResults(const std::filesystem::path& file, const std::filesystem::path& dataset,
                                const MapVisitor& visit, ResultsFile* header);
/// The same, every map kept in memory (Summary: without thresholds): for compare, plot and diff.
[[nodiscard]] ResultsFile readCheckedResults(const std::filesystem::path& file, MapDetail detail);

}  // namespace occsweep
