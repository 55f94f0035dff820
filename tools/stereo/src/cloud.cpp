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

// Indices of `keys` ordered by key, then by index. A frame's voxels span a few hundred per axis, so the key
// relative to the smallest one packs into far fewer than 64 bits and a stable radix sort on it, a byte per pass
// over the bytes it needs, gives that order in linear time; a span too wide to pack takes a comparison sort.
std::vector<std::uint32_t> voxelOrder(const std::vector<std::array<std::int64_t, 3>>& keys) {
  std::vector<std::uint32_t> order(keys.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = std::uint32_t(i);
  if (keys.empty()) return order;
  std::array<std::int64_t, 3> low = keys[0], high = keys[0];
  for (const auto& k : keys)
    for (int a = 0; a < 3; ++a) low[a] = std::min(low[a], k[a]), high[a] = std::max(high[a], k[a]);
  std::array<std::uint64_t, 3> span{};
  for (int a = 0; a < 3; ++a) span[a] = std::uint64_t(high[a] - low[a]) + 1;
  constexpr std::uint64_t kLimit = std::uint64_t(1) << 21;  // per axis, so that the packed key fits in 63 bits
  if (span[0] > kLimit || span[1] > kLimit || span[2] > kLimit) {
    std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
      return keys[a] != keys[b] ? keys[a] < keys[b] : a < b;
    });
    return order;
  }
  std::vector<std::uint64_t> packed(keys.size());
  for (std::size_t i = 0; i < keys.size(); ++i)
    packed[i] = (std::uint64_t(keys[i][0] - low[0]) * span[1] + std::uint64_t(keys[i][1] - low[1])) * span[2] +
                std::uint64_t(keys[i][2] - low[2]);
  const std::uint64_t largest = span[0] * span[1] * span[2] - 1;
  std::vector<std::uint32_t> next(order.size());
  for (int shift = 0; shift < 64 && (largest >> shift) != 0; shift += 8) {
    std::array<std::size_t, 257> start{};
    for (const std::uint32_t i : order) start[((packed[i] >> shift) & 0xFF) + 1] += 1;
    for (std::size_t b = 1; b < start.size(); ++b) start[b] += start[b - 1];
    for (const std::uint32_t i : order) next[start[(packed[i] >> shift) & 0xFF]++] = i;
    order.swap(next);
  }
  return order;
}

}  // namespace

std::vector<Eigen::Vector3d> reprojectDisparity(const std::vector<std::int16_t>& disparity, const StereoCamera& cam,
                                                const CameraPose& pose, double max_depth) {
  std::vector<Eigen::Vector3d> out;
  forEachPoint(disparity, cam, pose, max_depth, [&](std::size_t, const Eigen::Vector3d& p) { out.push_back(p); });
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
  // voxelFilter's order, once: by voxel (z, y, x), then by index.
  requireVoxelFilterLeaf(leaf, "SharedVoxelFilter");
  std::vector<VoxelFilterKey> keys(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) keys[i] = voxelFilterKey(points[i], leaf);
  const std::vector<std::uint32_t> order = voxelOrder(keys);
  points_.reserve(points.size());
  pixel_.reserve(points.size());
  for (std::size_t i = 0; i < order.size(); ++i) {
    points_.push_back(points[order[i]]);
    pixel_.push_back(pixels[order[i]]);
    if (i + 1 == order.size() || keys[order[i + 1]] != keys[order[i]]) voxel_end_.push_back(std::uint32_t(i + 1));
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
