// How a map's build runs its per-scan work on several threads without the core knowing the thread library: the
// caller (the sweep engine, `occsweep map`) passes a loop; the core splits the work so that the result is the same,
// voxel for voxel, whatever the loop does (docs/architecture.md, "Threads").
#pragma once

#include <algorithm>
#include <cstddef>
#include <functional>
#include <vector>


namespace occsweep {

/// A parallel loop: `for_each(count, body)` runs body(0) .. body(count - 1) in any order, on any threads, and
/// returns when every call has. Empty: each in order on this thread.
struct ScanExecutor {
  std::function<void(std::size_t count, const std::function<void(std::size_t)>& body)> for_each;
  std::size_t concurrency = 1;  ///< how many calls may run at once (sizes a build's batch of scans)

  void run(std::size_t count, const std::function<void(std::size_t)>& body) const;
};

// ---------------------------------------------------------------------------------------------------------

inline void ScanExecutor::run(std::size_t count, const std::function<void(std::size_t)>& body) const {
  if (for_each) {
    for_each(count, body);
    return;
  }
  for (std::size_t i = 0; i < count; ++i) body(i);
}

}  // namespace occsweep
