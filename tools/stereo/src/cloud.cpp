#include "occsweep/stereo/cloud.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace occsweep::stereo {
namespace {

// Calls add(pixel, point) for each valid disparity's point within max_depth, in pixel order.
template <class Add>
void forEachPoint(const std::vector<std::int16_t>& disparity, const StereoCamera& cam, const CameraPose& pose,
                  double max_depth, Add&& add) {
  for (int v = 0; v < cam.height; ++v)
    for (int u = 0; u < cam.width; ++u) {
      const std::size_t pixel = std::size_t(v) * cam.width + u;
      const std::int16_t raw = disparity[pixel];
      if (raw <= 0) continue;  // -16: no match; 0: infinitely far
      const double z = cam.fx * cam.baseline / (raw / 16.0);
      if (z > max_depth) continue;
      const Eigen::Vector3d in_camera((u - cam.cx) * z / cam.fx, (v - cam.cy) * z / cam.fx, z);
      add(pixel, Eigen::Vector3d(pose.position + pose.rotation * in_camera));
    }
}

}  // namespace

std::vector<Eigen::Vector3d> reprojectDisparity(const std::vector<std::int16_t>& disparity, const StereoCamera& cam,
                                                const CameraPose& pose, double max_depth) {
  std::vector<Eigen::Vector3d> out;
  forEachPoint(disparity, cam, pose, max_depth, [&](std::size_t, const Eigen::Vector3d& p) { out.push_back(p); });
  return out;
}

std::vector<octomap::point3d> voxelFilter(const std::vector<Eigen::Vector3d>& points, double leaf) {
  struct Keyed {
    std::array<std::int64_t, 3> key;  // z, y, x
    std::size_t index;
  };
  std::vector<Keyed> keyed;
  keyed.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto& p = points[i];
    keyed.push_back({{std::int64_t(std::floor(p.z() / leaf)), std::int64_t(std::floor(p.y() / leaf)),
                      std::int64_t(std::floor(p.x() / leaf))}, i});
  }
  // Stable order inside a voxel (by input index) so the centroid's rounding is reproducible.
  std::sort(keyed.begin(), keyed.end(),
            [](const Keyed& a, const Keyed& b) { return a.key != b.key ? a.key < b.key : a.index < b.index; });
  std::vector<octomap::point3d> out;
  for (std::size_t i = 0; i < keyed.size();) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    std::size_t j = i;
    for (; j < keyed.size() && keyed[j].key == keyed[i].key; ++j) sum += points[keyed[j].index];
    const Eigen::Vector3d c = sum / double(j - i);
    out.emplace_back(float(c.x()), float(c.y()), float(c.z()));
    i = j;
  }
  return out;
}

SharedVoxelFilter::SharedVoxelFilter(const std::vector<std::int16_t>& matcher_disparity, const StereoCamera& cam,
                                     const CameraPose& pose, double max_depth, double leaf) {
  std::vector<Eigen::Vector3d> points;
  std::vector<std::uint32_t> pixels;
  forEachPoint(matcher_disparity, cam, pose, max_depth, [&](std::size_t pixel, const Eigen::Vector3d& p) {
    points.push_back(p);
    pixels.push_back(std::uint32_t(pixel));
  });
  // voxelFilter's order, once: by voxel (z, y, x), then by index. Voxel indices within +-2^20 (+-100 km at
  // 0.1 m) pack into one 63-bit key in the same order; farther points (none in a scene) take the long way.
  using Key = std::array<std::int64_t, 3>;
  constexpr std::int64_t kOffset = std::int64_t(1) << 20;
  std::vector<Key> keys(points.size());
  bool packable = true;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto& p = points[i];
    keys[i] = {std::int64_t(std::floor(p.z() / leaf)), std::int64_t(std::floor(p.y() / leaf)),
               std::int64_t(std::floor(p.x() / leaf))};
    for (const std::int64_t k : keys[i]) packable = packable && k >= -kOffset && k < kOffset;
  }
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(points.size());  // (packed key, index)
  for (std::size_t i = 0; i < points.size(); ++i)
    keyed[i] = {packable ? std::uint64_t(keys[i][0] + kOffset) << 42 | std::uint64_t(keys[i][1] + kOffset) << 21 |
                               std::uint64_t(keys[i][2] + kOffset)
                         : 0,
                std::uint32_t(i)};
  if (packable) std::sort(keyed.begin(), keyed.end());
  else
    std::sort(keyed.begin(), keyed.end(), [&](const auto& a, const auto& b) {
      return keys[a.second] != keys[b.second] ? keys[a.second] < keys[b.second] : a.second < b.second;
    });
  points_.reserve(points.size());
  pixel_.reserve(points.size());
  for (std::size_t i = 0; i < keyed.size(); ++i) {
    points_.push_back(points[keyed[i].second]);
    pixel_.push_back(pixels[keyed[i].second]);
    if (i + 1 == keyed.size() || keys[keyed[i + 1].second] != keys[keyed[i].second])
      voxel_end_.push_back(std::uint32_t(i + 1));
  }
}

std::vector<octomap::point3d> SharedVoxelFilter::filtered(const std::vector<std::int16_t>& variant) const {
  std::vector<octomap::point3d> out;
  out.reserve(voxel_end_.size());
  std::size_t begin = 0;
  for (const std::uint32_t end : voxel_end_) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    std::size_t kept = 0;
    for (std::size_t j = begin; j < end; ++j) {
      if (variant[pixel_[j]] <= 0) continue;  // invalidated by the speckle filter
      sum += points_[j];
      kept += 1;
    }
    if (kept > 0) {
      const Eigen::Vector3d c = sum / double(kept);
      out.emplace_back(float(c.x()), float(c.y()), float(c.z()));
    }
    begin = end;
  }
  return out;
}

std::vector<octomap::point3d> toPoint3d(const std::vector<Eigen::Vector3d>& points) {
  std::vector<octomap::point3d> out;
  out.reserve(points.size());
  for (const auto& p : points) out.emplace_back(float(p.x()), float(p.y()), float(p.z()));
  return out;
}

}  // namespace occsweep::stereo
