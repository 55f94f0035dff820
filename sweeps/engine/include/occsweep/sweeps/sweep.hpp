// A sweep: one map per combination of the non-p_t parameters, thresholded at every p_t (docs/definitions.md,
// One map per combination).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "occsweep/core/map_settings.hpp"
#include "occsweep/sweeps/results.hpp"

namespace occsweep {

struct SweepConfig {
  std::filesystem::path dataset;  ///< data-set folder
  std::string grid = "knn-opt";   ///< grid name (sweeps/grids/NAME.json) or path
  SweepSelection selection;
  /// Results file: a store for ".db"/".sqlite", else JSON. While it runs, OUT.partial (store) or OUT.partial.jsonl
  /// (JSON) holds the finished maps.
  std::filesystem::path out;
  MapSettings map;                ///< what every map shares: resolution, s_c, variant, statistics mode
  int threads = 0;                ///< 0: all cores
  std::string engine = "replay";  ///< "replay" (record events once, replay each combination) or "direct"
                                  ///< (build every map: liboctomap for OctoMap, the k-NN mapper): the reference
  bool quiet = false;             ///< no progress on stderr
  bool force = false;             ///< replace occsweep's own results (or partial) of other work at `out`
  TruthMode truth = TruthMode::Full;  ///< which truth voxels count (docs/results-format.md, "Truth")
  /// With full truth: also write the observable-truth results of the same maps here, counted in the same pass
  /// (reproduce reports both truths without building any map twice). Empty: none.
  std::filesystem::path observable_out;
  friend bool operator==(const SweepConfig&, const SweepConfig&) = default;
};

/// The file a sweep into `out` writes its finished maps to while it runs: OUT.partial for a store, OUT.partial.jsonl
/// for JSON (docs/results-format.md).
[[nodiscard]] std::filesystem::path partialOutputPath(const std::filesystem::path& out);

/// What a sweep wrote, without its maps.
struct SweepSummary {
  ResultsHeader header;
  std::uint64_t maps = 0, combinations = 0;
  double seconds = 0.0;
};

/// Runs (or resumes) a sweep and writes its results atomically, in the format `out`'s name asks for: a results
/// store for ".db" or ".sqlite" (results_store.hpp: written batch by batch, memory independent of the grid's
/// size), JSON otherwise. A complete file of the same work is left as it is.
SweepSummary sweepToFile(const SweepConfig& config);

/// Several grids over one data set in one process (`occsweep sweep --grid A --grid B ...`): the data set is read,
/// its truth made and its events recorded once for all of them (docs/performance.md), then each grid is counted
/// into its own `out`. The configs differ only in grid, selection, out, observable_out, force and quiet; anything
/// else throws std::invalid_argument.
std::vector<SweepSummary> sweepGrids(const std::vector<SweepConfig>& configs);

/// The same, returning the results whole (read back from a store): for small sweeps.
ResultsFile runSweep(const SweepConfig& config);

}  // namespace occsweep
