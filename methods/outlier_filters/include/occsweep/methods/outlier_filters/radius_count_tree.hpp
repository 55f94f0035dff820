// FLANN's float metric, and how many points of a cloud lie within a radius of a point by it (ror-octomap's counts,
// point_filters.hpp) at a cost that does not grow with the radius (docs/methods.md, "Neighbour searches"): a k-d
// tree whose nodes hold their points' bounding box. A node wholly within the radius counts its points at once, one
// wholly beyond it none; only the points of the leaves the sphere's surface may cross are measured one by one.
#pragma once

#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

#include <octomap/octomap_types.h>

namespace occsweep::detail {

/// FLANN's L2_Simple<float> (flann/algorithms/dist.h), PCL KdTreeFLANN's metric: float differences, squared and
/// summed in float over x, y, z in that order (nanoflann's L2_Simple_Adaptor computes the same; the project builds
/// with -ffp-contract=off and Debian's libpcl has no FMA instructions, so no fused multiply-add on either side).
inline float flannSquaredDistance(const octomap::point3d& a, const octomap::point3d& b) {
  float result = 0.0f;
  for (unsigned dim = 0; dim < 3; ++dim) {
    const float diff = a(dim) - b(dim);
    result += diff * diff;
  }
  return result;
}

class RadiusCountTree {
 public:
  explicit RadiusCountTree(const std::vector<octomap::point3d>& points) : points_(points) {
    if (!points_.empty()) build(0, std::uint32_t(points_.size()));
  }

  /// The number of points p (q itself too, if it is one) with !(r2 < double(flannSquaredDistance(q, p))).
  [[nodiscard]] std::uint32_t countWithin(const octomap::point3d& q, double r2) {
    return points_.empty() ? 0 : count(0, q, r2);
  }

  /// The distances measured one by one so far: the work the boxes did not settle.
  [[nodiscard]] std::uint64_t distancesMeasured() const { return measured_; }

 private:
  struct Node {
    float lo[3], hi[3];         ///< the bounding box of its points
    std::uint32_t begin, end;   ///< its points in points_
    std::uint32_t second = 0;   ///< the node of its second half (the first follows it); 0 for a leaf
  };
  static constexpr std::uint32_t kLeafSize = 8;

  // Halves at the median of the box's longest side, depth first: a node's first half is the next node.
  std::uint32_t build(std::uint32_t begin, std::uint32_t end) {
    const auto id = std::uint32_t(nodes_.size());
    Node n{{}, {}, begin, end};
    for (unsigned a = 0; a < 3; ++a) n.lo[a] = n.hi[a] = points_[begin](a);
    for (std::uint32_t j = begin; j < end; ++j)
      for (unsigned a = 0; a < 3; ++a) {
        n.lo[a] = std::min(n.lo[a], points_[j](a));
        n.hi[a] = std::max(n.hi[a], points_[j](a));
      }
    nodes_.push_back(n);
    if (end - begin <= kLeafSize) return id;
    unsigned axis = 0;
    for (unsigned a = 1; a < 3; ++a)
      if (double(n.hi[a]) - n.lo[a] > double(n.hi[axis]) - n.lo[axis]) axis = a;
    const std::uint32_t middle = begin + (end - begin) / 2;
    std::nth_element(points_.begin() + begin, points_.begin() + middle, points_.begin() + end,
                     [axis](const octomap::point3d& a, const octomap::point3d& b) { return a(axis) < b(axis); });
    build(begin, middle);
    const std::uint32_t second = build(middle, end);
    nodes_[id].second = second;
    return id;
  }

  // The box's nearest and farthest squared distances from q, in double from the float coordinates (a few double
  // roundings). FLANN's float d2 of a point lies within 5 float roundings of its exact value (2^-24 each, relative,
  // or 2^-150 below the normal floats): far inside the margins of 2^-12 and 2^-126 used here.
  std::uint32_t count(std::uint32_t id, const octomap::point3d& q, double r2) {
    const Node& n = nodes_[id];
    double near2 = 0, far2 = 0;
    for (unsigned a = 0; a < 3; ++a) {
      const double below = double(n.lo[a]) - q(a), above = double(n.hi[a]) - q(a);
      const double gap = std::max({below, -above, 0.0}), reach = std::max(-below, above);
      near2 += gap * gap, far2 += reach * reach;
    }
    constexpr double kRelative = 0x1p-12, kAbsolute = 0x1p-126;
    if (near2 * (1 - kRelative) - kAbsolute > r2) return 0;  // every float d2 > r2 (or overflows to +inf)
    // every float d2 <= r2 and finite (one that overflowed to +inf would not count)
    if (far2 * (1 + kRelative) + kAbsolute <= std::min(r2, double(std::numeric_limits<float>::max())))
      return n.end - n.begin;
    if (n.second != 0) return count(id + 1, q, r2) + count(n.second, q, r2);
    std::uint32_t within = 0;
    for (std::uint32_t j = n.begin; j < n.end; ++j) within += !(r2 < double(flannSquaredDistance(q, points_[j])));
    measured_ += n.end - n.begin;
    return within;
  }

  std::vector<octomap::point3d> points_;  ///< the cloud's points, reordered into the tree's nodes
  std::vector<Node> nodes_;
  std::uint64_t measured_ = 0;
};

}  // namespace occsweep::detail
