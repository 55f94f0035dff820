// The voxel filter before mapping: PCL 1.13's pcl::VoxelGrid<PointXYZ> (the filter of the paper's Section 4.2) on an
// unorganised, dense cloud with default settings otherwise (no field limits, min_points_per_voxel 0,
// downsample_all_data irrelevant for x y z). One home for the stereo generator (tools/stereo, `dataset generate`
// and `dataset middlebury`) and the importers (`import ... --voxel-filter`, tools/data, which need no OpenCV).
// Line numbers cite PCL 1.13.0 as Debian 12 installs it (/usr/include/pcl-1.13/pcl/filters/impl/voxel_grid.hpp);
// docs/datasets.md, "Voxel filter", gives the semantics in prose, and tests/core/test_point_filters_pcl.cpp checks
// them against PCL itself.
//
// Where we differ from PCL, and why (the first two only by float rounding, which moves a point into another voxel
// only within float ulps of a voxel face; the third only for clouds PCL refuses):
// - The voxel index. PCL: floor(float(x) * inverse_leaf) with inverse_leaf = 1.0f / float(leaf), all in float
//   (:341-343). Ours: floor(x / leaf) in double. They agree except for points within a few float ulps of a voxel
//   face, where PCL's two float roundings may put a point into the neighbouring voxel. Ours is the exact answer for
//   the double coordinates the stereo generator has (docs/fidelity.md, "Two things found on the way").
// - The centroid. PCL sums the points as Eigen::Vector4f in float, in the order its (unstable) spreadsort left them
//   (:354, :421-426), and divides by float(n). Ours sums in double in input order, divides by n and rounds once to
//   float: the same value up to float rounding (the test bounds it), and independent of sort stability.
// - The size check. PCL returns the input unchanged, with a warning, when the cloud's bounding box spans more than
//   INT32_MAX voxels (:249-258); ours keys voxels with 64-bit integers and filters any cloud.
// Order is the same: PCL's linear index x + dx (y + dy z) (:341-346) sorts voxels by z, then y, then x.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <octomap/octomap_types.h>

namespace occsweep {

/// A point's voxel at `leaf`: floor(p / leaf) per axis, in double, as (z, y, x) so that keys sort in PCL's order.
using VoxelFilterKey = std::array<std::int64_t, 3>;

/// The key of `p` at `leaf`. The caller has checked leaf and point (voxelFilter does).
[[nodiscard]] inline VoxelFilterKey voxelFilterKey(const Eigen::Vector3d& p, double leaf) {
  return {std::int64_t(std::floor(p.z() / leaf)), std::int64_t(std::floor(p.y() / leaf)),
          std::int64_t(std::floor(p.x() / leaf))};
}

/// Throws std::invalid_argument unless `leaf` is a finite number above 0 (`who` names the caller's flag).
inline void requireVoxelFilterLeaf(double leaf, const std::string& who) {
  if (!(leaf > 0) || !std::isfinite(leaf))
    throw std::invalid_argument(who + ": the voxel filter's leaf must be a finite number above 0 (metres), not " +
                                std::to_string(leaf));
}

/// One point per occupied voxel at the centroid of its points (PCL VoxelGrid, see the file comment), ordered by
/// voxel (z, then y, then x), so the result does not depend on the input order. Throws std::invalid_argument for a
/// bad leaf, a point that is not finite, or one whose voxel index does not fit 62 bits (PCL would overflow far
/// earlier).
[[nodiscard]] inline std::vector<octomap::point3d> voxelFilter(const std::vector<Eigen::Vector3d>& points,
                                                               double leaf) {
  requireVoxelFilterLeaf(leaf, "voxelFilter");
  constexpr double kLargestIndex = 0x1p62;
  struct Keyed {
    VoxelFilterKey key;
    std::size_t index;
  };
  std::vector<Keyed> keyed;
  keyed.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3d& p = points[i];
    if (!((p / leaf).cwiseAbs().maxCoeff() < kLargestIndex))  // also false for NaN
      throw std::invalid_argument("voxelFilter: point " + std::to_string(i) + " is not finite or too far out");
    keyed.push_back({voxelFilterKey(p, leaf), i});
  }
  // Stable order inside a voxel (by input index), so the centroid's rounding is reproducible.
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

/// The same filter on stored points (the data-set format's float): each widened exactly to double first, so a
/// scan filtered here equals the stereo generator's filter of the same coordinates.
[[nodiscard]] inline std::vector<octomap::point3d> voxelFilter(const std::vector<octomap::point3d>& points,
                                                               double leaf) {
  std::vector<Eigen::Vector3d> wide;
  wide.reserve(points.size());
  for (const auto& p : points) wide.emplace_back(double(p.x()), double(p.y()), double(p.z()));
  return voxelFilter(wide, leaf);
}

}  // namespace occsweep
