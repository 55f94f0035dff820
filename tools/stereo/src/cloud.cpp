#include "occsweep/stereo/cloud.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace occsweep::stereo {

std::vector<Eigen::Vector3d> reprojectDisparity(const std::vector<std::int16_t>& disparity, const StereoCamera& cam,
                                                const CameraPose& pose, double max_depth) {
  std::vector<Eigen::Vector3d> out;
  for (int v = 0; v < cam.height; ++v)
    for (int u = 0; u < cam.width; ++u) {
      const std::int16_t raw = disparity[std::size_t(v) * cam.width + u];
      if (raw <= 0) continue;  // -16: no match; 0: infinitely far
      const double z = cam.fx * cam.baseline / (raw / 16.0);
      if (z > max_depth) continue;
      const Eigen::Vector3d in_camera((u - cam.cx) * z / cam.fx, (v - cam.cy) * z / cam.fx, z);
      out.push_back(pose.position + pose.rotation * in_camera);
    }
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

std::vector<octomap::point3d> toPoint3d(const std::vector<Eigen::Vector3d>& points) {
  std::vector<octomap::point3d> out;
  out.reserve(points.size());
  for (const auto& p : points) out.emplace_back(float(p.x()), float(p.y()), float(p.z()));
  return out;
}

}  // namespace occsweep::stereo
