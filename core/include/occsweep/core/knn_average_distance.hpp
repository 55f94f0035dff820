// s_i of Section 3.1: the mean Euclidean distance from each point to its k nearest other points.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include <nanoflann.hpp>
#include <octomap/octomap_types.h>

namespace occsweep {

/// Average distance from every point of `points` to its k nearest *other* points (itself excluded by index,
/// so a duplicate at distance 0 still counts as a neighbour). Fewer than k others: the mean over those there
/// are; none: +inf (docs/definitions.md, k-NN inverse sensor model). Distances are recomputed in double from
/// the float coordinates so the result does not depend on nanoflann's float accumulation or on how it breaks ties.
[[nodiscard]] std::vector<double> averageKnnDistances(const std::vector<octomap::point3d>& points, int k);

/// The same by brute force, O(n^2): the oracle the tests compare the k-d tree against.
[[nodiscard]] std::vector<double> averageKnnDistancesBruteForce(const std::vector<octomap::point3d>& points,
                                                                int k);

// ---------------------------------------------------------------------------------------------------------
namespace detail {

// The one adaptor between our points and nanoflann 1.4.3's pre-1.5 API (Debian 12's version).
struct PointVectorAdaptor {
  const std::vector<octomap::point3d>& pts;
  [[nodiscard]] std::size_t kdtree_get_point_count() const { return pts.size(); }
  [[nodiscard]] float kdtree_get_pt(std::size_t i, std::size_t dim) const { return pts[i](dim); }
  template <class BBox>
  bool kdtree_get_bbox(BBox&) const {
    return false;
  }
};

using KdTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, PointVectorAdaptor>,
                                                   PointVectorAdaptor, 3, std::uint32_t>;

inline double euclidean(const octomap::point3d& a, const octomap::point3d& b) {
  const double dx = double(a.x()) - double(b.x());
  const double dy = double(a.y()) - double(b.y());
  const double dz = double(a.z()) - double(b.z());
  return std::sqrt(dx * dx + dy * dy + dz * dz);
}

}  // namespace detail

inline std::vector<double> averageKnnDistances(const std::vector<octomap::point3d>& points, int k) {
  const std::size_t n = points.size();
  std::vector<double> s(n, std::numeric_limits<double>::infinity());
  if (n < 2 || k < 1) return s;
  detail::PointVectorAdaptor adaptor{points};
  detail::KdTree tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(10));
  tree.buildIndex();
  const std::size_t want = std::min<std::size_t>(std::size_t(k) + 1, n);
  std::vector<std::uint32_t> idx(want);
  std::vector<float> d2(want);
  for (std::size_t i = 0; i < n; ++i) {
    const float q[3] = {points[i].x(), points[i].y(), points[i].z()};
    const std::size_t found = tree.knnSearch(q, want, idx.data(), d2.data());
    double sum = 0.0;
    std::size_t used = 0;
    for (std::size_t j = 0; j < found && used < std::size_t(k); ++j) {
      if (idx[j] == i) continue;
      sum += detail::euclidean(points[i], points[idx[j]]);
      ++used;
    }
    if (used > 0) s[i] = sum / double(used);
  }
  return s;
}

inline std::vector<double> averageKnnDistancesBruteForce(const std::vector<octomap::point3d>& points, int k) {
  const std::size_t n = points.size();
  std::vector<double> s(n, std::numeric_limits<double>::infinity());
  std::vector<double> d;
  for (std::size_t i = 0; i < n; ++i) {
    d.clear();
    for (std::size_t j = 0; j < n; ++j)
      if (j != i) d.push_back(detail::euclidean(points[i], points[j]));
    const std::size_t used = std::min<std::size_t>(std::size_t(std::max(k, 0)), d.size());
    if (used == 0) continue;
    std::partial_sort(d.begin(), d.begin() + long(used), d.end());
    double sum = 0.0;
    for (std::size_t j = 0; j < used; ++j) sum += d[j];
    s[i] = sum / double(used);
  }
  return s;
}

}  // namespace occsweep
