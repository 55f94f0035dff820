// s_i of Section 3.1: the mean Euclidean distance from each point to its k nearest other points.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <nanoflann.hpp>
#include <octomap/octomap_types.h>

#include "cell_grid_knn.hpp"
#include "occsweep/core/limits.hpp"

namespace occsweep {

/// Average distance from every point of `points` to its k nearest *other* points (itself excluded by index,
/// so a duplicate at distance 0 still counts as a neighbour). Fewer than k others: the mean over those there
/// are; none: +inf (docs/definitions.md, k-NN inverse sensor model). Distances are computed in double from the
/// float coordinates and summed in ascending order, so s_i is one number whichever of several equally distant
/// points is taken: tied points have equal distances, and any order of equal values sums to the same double.
/// Searched over a grid of cells (cell_grid_knn.hpp, docs/performance.md), after checkNeighbourDistances.
[[nodiscard]] std::vector<double> averageKnnDistances(const std::vector<octomap::point3d>& points, int k);

/// The same for several k from one search with the largest: each k's s_i sums the first k of the same
/// ascending distances, so it equals averageKnnDistances(points, k) bit for bit. One vector per entry of ks.
[[nodiscard]] std::vector<std::vector<double>> averageKnnDistancesForEachK(const std::vector<octomap::point3d>& points,
                                                                          const std::vector<int>& ks);

/// Refuses, before a search for the k nearest other points of each of n points starts, more neighbour distances
/// than limits().neighbour_distances: n x min(k, n - 1), k capped at the cloud's size as PCL caps it, which gives
/// the same distances (docs/methods.md, "Neighbour searches"). `what` names the method, its k and the points.
void checkNeighbourDistances(const std::string& what, std::uint64_t n, std::uint64_t k);

/// The same by brute force, O(n^2): the oracle the tests compare the searches against.
[[nodiscard]] std::vector<double> averageKnnDistancesBruteForce(const std::vector<octomap::point3d>& points,
                                                                int k);

/// The same over a nanoflann k-d tree, which ranks by float squared distances and sums in its order: the
/// search before the grid of cells, kept for bench_sweep's comparison of the two on the same clouds. Equal to
/// averageKnnDistances except where two float squared distances round to one order and the doubles to the
/// other (a last-bit difference in s_i).
[[nodiscard]] std::vector<double> averageKnnDistancesKdTree(const std::vector<octomap::point3d>& points, int k);

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
  return std::sqrt(squaredDistance(a, b));
}

/// The mean of the square roots of ascending squared distances, summed in that order; +inf for none.
inline double meanOfRoots(const std::vector<double>& ascending_d2, std::size_t count) {
  if (count == 0) return std::numeric_limits<double>::infinity();
  double sum = 0.0;
  for (std::size_t j = 0; j < count; ++j) sum += std::sqrt(ascending_d2[j]);
  return sum / double(count);
}

}  // namespace detail

inline void checkNeighbourDistances(const std::string& what, std::uint64_t n, std::uint64_t k) {
  checkLimit(what + ": neighbour distances (points x min(k, points - 1))",
             saturatingProduct(n, std::min(k, n == 0 ? 0 : n - 1)), limits().neighbour_distances,
             "--max-neighbour-distances, or a smaller k");
}

inline std::vector<double> averageKnnDistances(const std::vector<octomap::point3d>& points, int k) {
  return std::move(averageKnnDistancesForEachK(points, {k}).front());
}

inline std::vector<std::vector<double>> averageKnnDistancesForEachK(const std::vector<octomap::point3d>& points,
                                                                   const std::vector<int>& ks) {
  const std::size_t n = points.size();
  const int k_max = ks.empty() ? 0 : *std::max_element(ks.begin(), ks.end());
  std::vector<std::vector<double>> s(ks.size(), std::vector<double>(n, std::numeric_limits<double>::infinity()));
  if (n < 2 || k_max < 1) return s;
  checkNeighbourDistances(
      "knn: k " + std::to_string(k_max) + " on the " + std::to_string(n) + " points of a scan within s_c", n,
      std::uint64_t(k_max));
  const CellGridKnn grid(points, k_max);
  grid.forEachPointNearestOthers(k_max, [&](std::size_t i, const std::vector<double>& ascending_d2) {
    for (std::size_t m = 0; m < ks.size(); ++m)
      s[m][i] = detail::meanOfRoots(ascending_d2, std::min<std::size_t>(std::size_t(std::max(ks[m], 0)), ascending_d2.size()));
  });
  return s;
}

inline std::vector<double> averageKnnDistancesKdTree(const std::vector<octomap::point3d>& points, int k) {
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
