// `occsweep dataset generate` as a function: the command and `reproduce` (its missing data sets) run this one code
// path, in this process (docs/datasets.md).
#pragma once

#include <cstdint>
#include <string>

namespace occsweep::cli {

/// The options of `dataset generate` (docs/datasets.md, "Realism and experiment options" for the realism ones).
struct DatasetOptions {
  std::string name, out, scale = "ci", sgbm, pcs, grid = "pointcloud";
  bool all = false, no_preview = false;
  std::uint64_t seed = 1;
  double drift_m = 0, drift_yaw = 0;
  int threads = 0;
  std::string pose_error, exposure;
  double jitter_m = 0, jitter_deg = 0;
  double right_gain = 1, right_offset = 0, right_gamma = 1, right_vignetting = 0;
  bool far_clutter = false, no_voxel_filter = false, realistic = false;
  double box_height = 0.5, noise_scale = 1;
  bool quiet = false;  ///< no progress on stderr
  bool force = false;  ///< replace occsweep's own earlier output at the data sets' names
};

/// Generates the data sets `o` names under o.out (OUT/NAME/pcs-*/, OUT/NAME/ranking.json last) and prints one
/// summary line per data set. Throws std::invalid_argument for inconsistent options, std::runtime_error when this
/// build has no stereo tools.
void generateDatasets(const DatasetOptions& o);

}  // namespace occsweep::cli
