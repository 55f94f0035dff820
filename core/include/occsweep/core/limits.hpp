// What an input may make occsweep allocate or compute: every size an input controls is computed in
// 64 bits and checked against one of these limits before anything is allocated. The values, why they were
// chosen and the flags that raise them are in docs/robustness.md ("Limits and non-regular files").
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

namespace occsweep {

struct Limits {
  std::uint64_t window_voxels = std::uint64_t(1) << 26;   ///< k-NN key window of one scan (--max-window-voxels)
  std::uint64_t combinations = 2'000'000;                 ///< grid combinations enumerated (--max-combinations)
  std::uint64_t region_voxels = std::uint64_t(1) << 26;   ///< evaluation region (--max-region-voxels)
  std::uint64_t map_voxels = std::uint64_t(1) << 24;      ///< finest-depth voxels of a .ot read (--max-map-voxels)
  std::uint64_t image_pixels = std::uint64_t(1) << 23;    ///< one depth image (--max-image-pixels)
  std::uint64_t points = std::uint64_t(1) << 24;          ///< points of a data set or an import (--max-points)
  std::uint64_t neighbour_distances = std::uint64_t(1) << 29;  ///< k nearest in a scan (--max-neighbour-distances)
  std::uint64_t json_bytes = std::uint64_t(1) << 27;      ///< bytes of a JSON input parsed whole (--max-json-bytes)
};

/// The process's limits: the defaults above, raised by the command's flags before it runs (then read-only).
inline Limits& limits() {
  static Limits l;
  return l;
}

/// A size past a limit: the message names what (file, field or flag), the size asked for, the limit and its flag.
class LimitError : public std::runtime_error {
 public:
  LimitError(const std::string& what, std::uint64_t size, std::uint64_t limit, const std::string& flag)
      : std::runtime_error(what + ": " + std::to_string(size) + " is more than the limit of " + std::to_string(limit) +
                           " (raise it with " + flag + "; see docs/robustness.md)") {}
};

/// Throws LimitError when size > limit.
inline void checkLimit(const std::string& what, std::uint64_t size, std::uint64_t limit, const std::string& flag) {
  if (size > limit) throw LimitError(what, size, limit, flag);
}

/// a * b, saturating at UINT64_MAX instead of wrapping.
[[nodiscard]] inline std::uint64_t saturatingProduct(std::uint64_t a, std::uint64_t b) {
  if (a != 0 && b > UINT64_MAX / a) return UINT64_MAX;
  return a * b;
}

}  // namespace occsweep
