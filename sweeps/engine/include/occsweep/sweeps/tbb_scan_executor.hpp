// The core's parallel loop (scan_executor.hpp) on TBB: the one place a build's per-scan work meets the thread
// library, for every caller below the command line that builds a core map on several threads (the engines, the
// reproduction's fits). The same map or distances, voxel for voxel, on any number of threads (docs/architecture.md,
// "Threads").
#pragma once

#include "occsweep/core/scan_executor.hpp"

namespace occsweep {

/// A ScanExecutor running on TBB's threads, as many as the task arena it is made in.
[[nodiscard]] ScanExecutor tbbScanExecutor();

}  // namespace occsweep
