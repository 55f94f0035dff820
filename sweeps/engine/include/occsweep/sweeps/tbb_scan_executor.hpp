// The core's parallel loop (scan_executor.hpp) on TBB, for the callers in sweeps/ that build a core map or its
// distances on several threads (the engines, the reproduction's fits): the same result, voxel for voxel, on any
// number of threads (docs/architecture.md, "Threads"). `occsweep map` makes its own in its task arena: the command
// includes no engine header.
#pragma once

#include "occsweep/core/scan_executor.hpp"

namespace occsweep {

/// A ScanExecutor running on TBB's threads, as many as the task arena it is made in.
[[nodiscard]] ScanExecutor tbbScanExecutor();

}  // namespace occsweep
