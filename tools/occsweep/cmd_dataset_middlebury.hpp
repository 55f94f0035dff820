// `dataset middlebury`, a subcommand of `dataset` (cmd_dataset.cpp) in its own file; and its code as a function,
// which `reproduce`'s real-stereo step runs in this process (docs/reproduction.md).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>

namespace occsweep::cli {

/// The options of `dataset middlebury` (docs/datasets.md, "Real stereo: Middlebury"). The inputs default to the
/// Aloe pair of Debian's opencv-doc (middleburyDefaults).
struct MiddleburyOptions {
  std::string left, right, gt, out, grid = "pointcloud";
  double leaf = 0.1, focal = 3740.0, baseline = 0.160, doffs = 270.0;
  double voxel_filter = 0;  ///< --voxel-filter: the filter's leaf; 0: --leaf
  bool no_voxel_filter = false;
};

/// The defaults, with the Aloe pair as inputs where this build has the stereo tools.
[[nodiscard]] MiddleburyOptions middleburyDefaults();

/// What writeMiddleburySets wrote: OUT/pcs-NNNN per point cloud id, in id order, and their points.
struct MiddleburySetsWritten {
  std::vector<std::string> folders;
  std::vector<std::uint64_t> ids, points;
};

/// Empty when the three inputs exist and this build has the stereo tools; else why the pair cannot be read (the
/// package that installs the default files, or the missing build option).
[[nodiscard]] std::string middleburyUnavailable(const MiddleburyOptions& o);

/// `dataset middlebury` itself: the sets written under o.out, a line per set on stdout unless `quiet`. Throws
/// std::runtime_error naming the package when a default input is missing, or for a build without stereo tools.
MiddleburySetsWritten writeMiddleburySets(const MiddleburyOptions& o, bool quiet);

/// Adds `middlebury` to the `dataset` command; returns the subcommand and what runs it.
[[nodiscard]] std::pair<CLI::App*, std::function<int()>> addDatasetMiddlebury(CLI::App& dataset);

}  // namespace occsweep::cli
