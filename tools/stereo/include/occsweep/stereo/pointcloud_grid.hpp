// The point cloud parameter grid (sweeps/grids/pointcloud.json): StereoSGBM settings, each combination with a
// stable id, its index in the canonical enumeration (blockSize outermost, disp12MaxDiff innermost).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "sgbm.hpp"

namespace occsweep::stereo {

struct PointCloudGrid {
  std::string name;
  std::vector<int> block_size, uniqueness_ratio, speckle_window_size, speckle_range, disp12_max_diff;
  std::string file_hash;  ///< FNV-1a 64 of the file's bytes

  [[nodiscard]] std::uint64_t size() const;
  /// The combination with this id; throws std::out_of_range beyond size().
  [[nodiscard]] SgbmParams at(std::uint64_t id) const;
};

/// Throws std::runtime_error naming the file, the key and the rule: unknown or missing keys, empty lists,
/// repeated values, or values SgbmParams refuses.
[[nodiscard]] PointCloudGrid parsePointCloudGrid(const nlohmann::json& j, const std::string& file);
[[nodiscard]] PointCloudGrid loadPointCloudGrid(const std::filesystem::path& file);

/// `count` ids spread evenly over [0, size): round(i (size - 1) / (count - 1)), so the first and the last
/// combination are always in; all ids when count >= size.
[[nodiscard]] std::vector<std::uint64_t> evenSubset(std::uint64_t size, std::uint64_t count);

}  // namespace occsweep::stereo
