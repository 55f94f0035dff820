#include "occsweep/sweeps/tbb_scan_executor.hpp"

#include <algorithm>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

namespace occsweep {

ScanExecutor tbbScanExecutor() {
  const auto for_each = [](std::size_t count, const std::function<void(std::size_t)>& body) {
    tbb::parallel_for(std::size_t(0), count, [&](std::size_t t) { body(t); });
  };
  return {for_each, std::size_t(std::max(1, tbb::this_task_arena::max_concurrency()))};
}

}  // namespace occsweep
