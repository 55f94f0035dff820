// A point cloud set: the scans of one data set, each with its sensor origin, points in the world frame.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include <octomap/octomap_types.h>

#include "sensor_view.hpp"

namespace occsweep {

/// One scan z_t taken from sensor origin x_t. Points are in the world frame, like the clouds OctoMap inserts.
/// `view`: what the sensor could see from the origin, when the data set records it (observable truth only).
struct Scan {
  octomap::point3d origin;
  std::vector<octomap::point3d> points;
  std::optional<SensorView> view;
};

/// The ordered scans of one data set under one set of point cloud parameters.
using PointCloudSet = std::vector<Scan>;

[[nodiscard]] inline std::size_t pointCount(const PointCloudSet& set) {
  std::size_t n = 0;
  for (const auto& scan : set) n += scan.points.size();
  return n;
}

/// Distance from the sensor as OctoMap measures it in computeUpdate: (p - origin).norm(), float
/// components, so that our in/out split at s_c matches liboctomap's maxrange test bit for bit.
[[nodiscard]] inline double rangeFromOrigin(const octomap::point3d& p, const octomap::point3d& origin) {
  return (p - origin).norm();
}

/// The in-range points of a scan, z_in (OctoMap's maxrange test: (p - origin).norm() <= s_c), as indices into its
/// points in point order; the others cast a ray cut at s_c and are no hit.
[[nodiscard]] inline std::vector<std::uint32_t> innerPoints(const Scan& scan, double s_c) {
  std::vector<std::uint32_t> inner;
  inner.reserve(scan.points.size());
  for (std::uint32_t i = 0; i < scan.points.size(); ++i)
    if (rangeFromOrigin(scan.points[i], scan.origin) <= s_c) inner.push_back(i);
  return inner;
}

}  // namespace occsweep
