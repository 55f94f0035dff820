// How a sweep turns its maps into TP/FP/FN/TN counts (SweepConfig::engine): replay every map from the region
// voxels' recorded events (replay.hpp), or build every map directly with its method's own builder (the
// reference). runSweep (sweep_run.cpp) does everything else alike for both.
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "occsweep/core/mapping_method.hpp"
#include "occsweep/core/point_cloud_set.hpp"
#include "occsweep/eval/confusion.hpp"
#include "occsweep/eval/ground_truth.hpp"
#include "occsweep/sweeps/grid.hpp"
#include "occsweep/sweeps/sweep.hpp"

namespace occsweep {

/// One map a sweep counts: its parameters and the p_t values of its selected thresholds.
struct MapToCount {
  const MapParams* params = nullptr;
  std::vector<double> p_t;
};

/// One grid's maps: a sweep counts one grid, or several over one data set with one recording (sweepGrids).
struct GridMaps {
  const MappingMethod* method = nullptr;      ///< the grid's method (docs/methods.md)
  const ParameterLayout* layout = nullptr;    ///< its parameters, the order of MapParams::values
  const std::vector<MapToCount>* maps = nullptr;
};

/// What every map of a sweep shares.
struct SweepInputs {
  const SweepConfig& config;
  PointCloudSet& scans;       ///< the data set's points; an engine frees them once it no longer needs them
  const GroundTruth& truth;   ///< the truth the results count (SweepConfig::truth)
  /// The truth with its unobservable voxels in `excluded` when the sweep counts observable truth or has a twin
  /// (SweepConfig::observable_out); otherwise the full truth.
  const GroundTruth& marked;
  bool twin = false;          ///< also count every map under observable truth
};

/// Per map of a batch, per threshold: the counts under the sweep's truth, and (twin only) under observable truth.
struct BatchCounts {
  std::vector<std::vector<ConfusionCounts>> counts, observable;
};

class SweepEngine {
 public:
  virtual ~SweepEngine() = default;

  /// "replay" or "direct": SweepConfig::engine, and what results record (map.engine, map.engines and each line of
  /// the partial log: docs/results-format.md).
  [[nodiscard]] virtual std::string name() const = 0;

  /// Computes what the maps of every grid share (replay: the recorded events, once for all grids, with the gate
  /// extremes of every filter, and each hit feature at the recorded hits; direct: what the maps share, each by its
  /// identity on first use). Runs TBB loops in the caller's arena; keeps references to `inputs`' truths and points
  /// and to `grids` (which must outlive the counting).
  virtual void prepare(const SweepInputs& inputs, const std::vector<GridMaps>& grids) = 0;

  /// The maps of grid `grid` counted together, as indices into its maps, each map once: replay, up to
  /// 4 x kReplayPassLanes maps that share their hit rule and gate feature (the method's sharedByLanes: k-NN's k,
  /// p_u, p_l); direct, one map each.
  [[nodiscard]] virtual std::vector<std::vector<std::size_t>> batches(std::size_t grid) const = 0;

  /// The counts of one batch of grid `grid`, in the batch's order. Safe to call from several threads at once
  /// after prepare.
  [[nodiscard]] virtual BatchCounts count(std::size_t grid, const std::vector<std::size_t>& batch) const = 0;
};

/// The names makeSweepEngine accepts, in the order CLI11's IsMember lists them: replay (the default), direct.
[[nodiscard]] std::vector<std::string> sweepEngineNames();

/// The engine of that name; throws std::invalid_argument naming it and the accepted names.
[[nodiscard]] std::unique_ptr<SweepEngine> makeSweepEngine(std::string_view name);

}  // namespace occsweep
