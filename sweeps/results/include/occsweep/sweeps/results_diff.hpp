// A regression check of one results file against a golden one (`occsweep results diff`, docs/results-format.md,
// "Regression checks against a golden file"): what changed, combination by combination.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "occsweep/sweeps/results.hpp"

namespace occsweep {

/// One thing that differs. A header field has no map; a count, a missing combination or a p_t names the
/// combination's id; an AUC is a map's (its combinations share it), so it names the map alone.
struct ResultsDifference {
  std::optional<std::uint64_t> map_index;  ///< the golden map concerned (none for a header field)
  std::optional<std::uint64_t> id;         ///< the combination's stable id (none for a map's or header's field)
  std::string combination;                 ///< its parameters as text, "p_max=0.98 ... p_t=0.5" ("" for a header)
  std::string field;                       ///< "grid.file_hash", "tp", "auc.anchored", "combination", ...
  std::string golden, candidate;           ///< the field's value in each file ("missing" when absent)
};

struct ResultsDiff {
  /// Header fields that make the files incomparable. When there is one, no combination is compared: every number
  /// would differ for a reason the header already gives.
  std::vector<ResultsDifference> header;
  std::vector<ResultsDifference> combinations;  ///< by golden map, then id; extra ones of the candidate last
  std::uint64_t golden_maps = 0, golden_combinations = 0;

  [[nodiscard]] bool empty() const { return header.empty() && combinations.empty(); }
};

/// Whether diffResults compares the confusion counts. An AUC is computed from its map's counts, so a tolerance on
/// it only means something when the counts may differ: Ignored checks the AUCs alone (a downstream mapper's change
/// that may move voxels but must not move its AUCs by more than the tolerance).
enum class CountsCheck { Exact, Ignored };

/// Compares `candidate` with `golden`: header fields that make the files incomparable (grid, data set, selection,
/// map settings, truth; version, commit, engine and timings do not count), every golden combination missing from
/// the candidate or (CountsCheck::Exact) with other TP/FP/FN/TN, every map whose anchored or observed AUC moved by
/// more than `auc_tolerance` (NaN equals only NaN), and combinations the golden file does not hold.
[[nodiscard]] ResultsDiff diffResults(const ResultsFile& golden, const ResultsFile& candidate, double auc_tolerance,
                                      CountsCheck counts = CountsCheck::Exact);

/// The header fields of `a` and `b` that make them incomparable, with their values; shard index and count only
/// when `compare_shard` (merging compares shards of one work). `sameWork` is the first of these.
[[nodiscard]] std::vector<ResultsDifference> incomparableHeaderFields(const ResultsHeader& a, const ResultsHeader& b,
                                                                      bool compare_shard);

/// A map's parameters as text, with `p_t` when given: "p_max=0.98 p_min=0.02 p_h=0.7 p_m=0.4 p_t=0.5".
[[nodiscard]] std::string combinationText(const MapParams& params, const ParameterLayout& parameters,
                                           std::optional<Fixed> p_t);

}  // namespace occsweep
