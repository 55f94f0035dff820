// PCL 1.13's two point cloud outlier filters, reproduced bit for bit for the sor-octomap and ror-octomap baselines:
// pcl::StatisticalOutlierRemoval<PointXYZ> and pcl::RadiusOutlierRemoval<PointXYZ> on an unorganised, dense cloud
// (height 1, is_dense true: what a pcl::PointCloud built from finite points is), default settings otherwise
// (negative off, all indices). Line numbers cite PCL 1.13.0 as Debian 12 installs it (libpcl-dev 1.13.0+dfsg-3,
// /usr/include/pcl-1.13/pcl/...); docs/methods.md gives the semantics in prose.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <octomap/octomap_types.h>

#include "occsweep/methods/knn/knn_average_distance.hpp"  // detail::PointVectorAdaptor, detail::KdTree
#include "radius_count_tree.hpp"     // detail::flannSquaredDistance, detail::RadiusCountTree

namespace occsweep {

/// PCL StatisticalOutlierRemoval's first pass over one cloud.
struct SorDistances {
  std::vector<float> mean_distance;                 // per point, exactly PCL's distances[i]
  double threshold_mean = 0, threshold_stddev = 0;  // PCL's mean and stddev (as PCL computes them)
};

/// PCL's first pass (filters/impl/statistical_outlier_removal.hpp:62-107). Per point: the mean_k+1 nearest squared
/// distances of the whole cloud (the point itself included, at 0), ascending; the first is skipped (:92, "k = 0 is
/// the query point": with duplicates it may be a twin, the sum is the same), the others summed as
/// sqrt(double(float d2)) in double (:93) and divided by mean_k (:94), even when the cloud holds fewer than mean_k+1
/// points (PCL then reads the zeros its buffer was filled with, :64 and kdtree_flann.hpp:243-247), then rounded to
/// float (:94). Mean and stddev over all points (:99-107): sample variance (n-1) by the one-pass formula, squares
/// taken in float (`distance * distance` of a float); one point gives 0/0 = NaN, an empty cloud NaN for both.
/// Points must be finite; mean_k >= 1 (PCL's mean_k 0 divides by zero). Throws std::invalid_argument otherwise,
/// LimitError for more than limits().neighbour_distances (checkNeighbourDistances) before searching.
[[nodiscard]] SorDistances sorDistances(const std::vector<octomap::point3d>& points, int mean_k);
/// PCL's distance_threshold = mean + std_mul * stddev, computed exactly as PCL does (:110).
[[nodiscard]] double sorThreshold(const SorDistances& d, double std_mul);
/// PCL's keep test for one point (true = inlier kept): exactly the negation of PCL's removal condition
/// `distances[iii] > distance_threshold` (:117), the float widened to double. A NaN threshold keeps every point.
[[nodiscard]] bool sorKeeps(float mean_distance, double threshold);
/// Indices of the kept points, ascending (PCL's filter output order, :113-125).
[[nodiscard]] std::vector<std::uint32_t> statisticalOutlierRemoval(const std::vector<octomap::point3d>& points,
                                                                   int mean_k, double std_mul);

/// Per point: the number of OTHER points j (duplicates included) with double(d2(i, j)) <= radius * radius in double,
/// d2 being FLANN's float squared distance. PCL 1.13 on a dense cloud does not call radiusSearch at all: it runs
/// nearestKSearch(i, min_pts + 1) and keeps the point iff it found min_pts + 1 points and
/// !(radius * radius < double(nn_dists[k-1])) (filters/impl/radius_outlier_removal.hpp:77-116), i.e. iff at
/// least min_pts others lie at double(d2) <= radius^2: a point exactly at the radius counts. So keep ==
/// (count >= min_neighbors) for every min_neighbors >= 0 and radius != 0 (min_neighbors 0 keeps every point:
/// k = 1 finds the point itself at 0). radius 0 is PCL's "No radius defined" branch (:51-57): nothing is kept,
/// whatever the counts; radiusOutlierRemoval reproduces it. A negative radius acts as |radius| (only its square
/// is used, :81). Points must be finite, radius not NaN; throws std::invalid_argument otherwise. Counted in a
/// RadiusCountTree (radius_count_tree.hpp): the cost does not grow with the radius.
[[nodiscard]] std::vector<std::uint32_t> rorNeighbourCounts(const std::vector<octomap::point3d>& points,
                                                            double radius);
/// PCL's keep test for a point with `neighbours` other points within the radius (radius != 0). min_neighbors < 0
/// throws std::invalid_argument: PCL's search for min_pts + 1 <= 0 points reads nn_dists[-1] or removes everything.
[[nodiscard]] bool rorKeeps(std::uint32_t neighbours, int min_neighbors);
/// Indices of the kept points, ascending (PCL's output order, :83-129); empty for radius 0 (:51-57).
[[nodiscard]] std::vector<std::uint32_t> radiusOutlierRemoval(const std::vector<octomap::point3d>& points,
                                                              double radius, int min_neighbors);

// ---------------------------------------------------------------------------------------------------------
namespace detail {

inline void requireFinite(const std::vector<octomap::point3d>& points, const char* who) {
  for (const auto& p : points)
    if (!std::isfinite(p.x()) || !std::isfinite(p.y()) || !std::isfinite(p.z()))
      throw std::invalid_argument(std::string(who) + ": a point is not finite");
}

/// A float bound a little above `squared_distance`, at least the smallest normal float. The k-d tree prunes a cell
/// on a lower bound it accumulates in float; rounding may lift that bound a few ulps above a point's true distance.
/// Searching to this bound and then deciding on recomputed distances makes the answer the exact one, whatever the
/// tree's shape (leaf size, split rule): FLANN's tree in PCL and nanoflann's are built differently, and only
/// distances, never indices or visiting order, decide what is kept.
inline float searchBound(double squared_distance) {
  const float widened = float(squared_distance * (1.0 + 0x1p-12));
  return std::max(std::nextafter(widened, std::numeric_limits<float>::infinity()),
                  std::numeric_limits<float>::min());
}

/// Exact nearest distances over one cloud: nanoflann finds candidates, FLANN's metric decides (see searchBound).
class ExactNeighbours {
 public:
  explicit ExactNeighbours(const std::vector<octomap::point3d>& points)
      : points_(points), adaptor_{points}, tree_(3, adaptor_, nanoflann::KDTreeSingleIndexAdaptorParams(10)) {
    tree_.buildIndex();
  }

  /// PCL's nn_dists of nearestKSearch(i, want) in d2: the `want` smallest squared distances to all points (i
  /// included, at 0), ascending; fewer when the cloud is smaller (kdtree_flann.hpp:243-247). Ties are equal
  /// values, so which tied point a tree returns cannot change them.
  void nearest(std::size_t i, std::size_t want) {
    const float q[3] = {points_[i].x(), points_[i].y(), points_[i].z()};
    // PCL caps k at the cloud's size (kdtree_flann.hpp:243-247): the same distances, no buffer beyond it.
    NearestSoFar<float> so_far(knn_d2_, std::min(want, points_.size()));
    NearestResults results{so_far};
    tree_.findNeighbors(results, q, nanoflann::SearchParams());
    // The want-th smallest distance is at most worst(), the want-th of some real points' nanoflann distances
    // (FLANN's formula; searchBound's margin would cover a last-bit difference too). Every point below the bound,
    // each distance recomputed, then the want smallest.
    const float bound = so_far.full() ? searchBound(so_far.worst()) : std::numeric_limits<float>::infinity();
    found_.clear();
    tree_.radiusSearch(q, bound, found_, nanoflann::SearchParams(32, 0.0f, false));
    NearestSoFar<float> exact(d2, want);
    for (const auto& [j, unused] : found_) exact.offer(flannSquaredDistance(points_[i], points_[j]));
    exact.sortAscending();
  }

  std::vector<float> d2;  ///< of the last nearest()

 private:
  /// nanoflann's result-set interface over NearestSoFar: nanoflann's own KNNResultSet keeps its array sorted,
  /// O(want) an offer, which made SOR's cost grow with the square of k.
  struct NearestResults {
    NearestSoFar<float>& so_far;
    [[nodiscard]] float worstDist() const { return so_far.worst(); }
    [[nodiscard]] bool full() const { return so_far.full(); }
    bool addPoint(float d2, std::uint32_t) { return so_far.offer(d2), true; }
  };

  const std::vector<octomap::point3d>& points_;
  PointVectorAdaptor adaptor_;
  KdTree tree_;
  std::vector<std::pair<std::uint32_t, float>> found_;
  std::vector<float> knn_d2_;
};

}  // namespace detail

inline SorDistances sorDistances(const std::vector<octomap::point3d>& points, int mean_k) {
  if (mean_k < 1) throw std::invalid_argument("sorDistances: mean_k must be at least 1");
  detail::requireFinite(points, "sorDistances");
  SorDistances out;
  const std::size_t n = points.size();
  checkNeighbourDistances(
      "sor-octomap: k " + std::to_string(mean_k) + " on a scan of " + std::to_string(n) + " points", n,
      std::uint64_t(mean_k));
  out.mean_distance.resize(n);
  if (n > 0) {
    detail::ExactNeighbours search(points);
    const std::size_t want = std::size_t(mean_k) + 1;  // :62, "one more, since results include the query point"
    for (std::size_t i = 0; i < n; ++i) {
      search.nearest(i, want);
      double dist_sum = 0.0;  // :91
      for (std::size_t k = 1; k < search.d2.size(); ++k) dist_sum += std::sqrt(double(search.d2[k]));  // :92-93
      out.mean_distance[i] = static_cast<float>(dist_sum / mean_k);         // :94, all n points are valid
    }
  }
  // :99-107, in PCL's order of operations (the variance can round below 0 for equal distances: stddev NaN then).
  double sum = 0, sq_sum = 0;
  for (const float& distance : out.mean_distance) {
    sum += distance;
    sq_sum += distance * distance;  // float * float, then widened (mulss; cvtss2sd in libpcl_filters.so)
  }
  const double valid_distances = static_cast<double>(n);
  out.threshold_mean = sum / valid_distances;
  const double variance = (sq_sum - sum * sum / valid_distances) / (valid_distances - 1);
  out.threshold_stddev = std::sqrt(variance);
  return out;
}

inline double sorThreshold(const SorDistances& d, double std_mul) {
  return d.threshold_mean + std_mul * d.threshold_stddev;
}

inline bool sorKeeps(float mean_distance, double threshold) { return !(double(mean_distance) > threshold); }

inline std::vector<std::uint32_t> statisticalOutlierRemoval(const std::vector<octomap::point3d>& points, int mean_k,
                                                            double std_mul) {
  const SorDistances d = sorDistances(points, mean_k);
  const double threshold = sorThreshold(d, std_mul);
  std::vector<std::uint32_t> kept;
  for (std::size_t i = 0; i < d.mean_distance.size(); ++i)
    if (sorKeeps(d.mean_distance[i], threshold)) kept.push_back(std::uint32_t(i));
  return kept;
}

inline std::vector<std::uint32_t> rorNeighbourCounts(const std::vector<octomap::point3d>& points, double radius) {
  if (std::isnan(radius)) throw std::invalid_argument("rorNeighbourCounts: radius is NaN");
  detail::requireFinite(points, "rorNeighbourCounts");
  const std::size_t n = points.size();
  std::vector<std::uint32_t> counts(n, 0);
  if (n == 0) return counts;
  const double nn_dists_max = radius * radius;  // radius_outlier_removal.hpp:81, double
  // :104 removes when nn_dists_max < nn_dists[k-1]: a neighbour counts iff that is false; the point itself, at 0,
  // always does.
  detail::RadiusCountTree tree(points);
  for (std::size_t i = 0; i < n; ++i) counts[i] = tree.countWithin(points[i], nn_dists_max) - 1;
  return counts;
}

inline bool rorKeeps(std::uint32_t neighbours, int min_neighbors) {
  if (min_neighbors < 0) throw std::invalid_argument("rorKeeps: min_neighbors must be at least 0");
  return neighbours >= std::uint32_t(min_neighbors);
}

inline std::vector<std::uint32_t> radiusOutlierRemoval(const std::vector<octomap::point3d>& points, double radius,
                                                       int min_neighbors) {
  if (min_neighbors < 0) throw std::invalid_argument("radiusOutlierRemoval: min_neighbors must be at least 0");
  const std::vector<std::uint32_t> counts = rorNeighbourCounts(points, radius);
  std::vector<std::uint32_t> kept;
  if (radius == 0.0) return kept;  // :51-57, "No radius defined!": PCL keeps nothing
  for (std::size_t i = 0; i < counts.size(); ++i)
    if (rorKeeps(counts[i], min_neighbors)) kept.push_back(std::uint32_t(i));
  return kept;
}

}  // namespace occsweep
