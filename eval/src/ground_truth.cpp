#include "occsweep/eval/ground_truth.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>

#include <octomap/OcTree.h>

#include "occsweep/core/limits.hpp"

namespace occsweep {
namespace {

using octomap::OcTreeKey;

// Inclusive key range of voxels whose centre lies in [lo, hi] along one axis.
std::pair<int, int> centreKeyRange(const octomap::OcTree& grid, double lo, double hi) {
  int a = grid.coordToKey(lo);
  if (grid.keyToCoord(octomap::key_type(a)) < lo) ++a;
  int b = grid.coordToKey(hi);
  if (grid.keyToCoord(octomap::key_type(b)) > hi) --b;
  return {a, b};
}

double dot(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
void cross(const double a[3], const double b[3], double out[3]) {
  out[0] = a[1] * b[2] - a[2] * b[1];
  out[1] = a[2] * b[0] - a[0] * b[2];
  out[2] = a[0] * b[1] - a[1] * b[0];
}

}  // namespace

bool GroundTruth::inRegion(const OcTreeKey& k) const {
  for (int i = 0; i < 3; ++i)
    if (k[i] < region_min_key[i] || k[i] > region_max_key[i]) return false;
  return true;
}

std::size_t GroundTruth::regionVoxelCount() const {
  std::size_t n = 1;
  for (int i = 0; i < 3; ++i) {
    if (region_max_key[i] < region_min_key[i]) return 0;
    n *= std::size_t(region_max_key[i] - region_min_key[i] + 1);
  }
  return n;
}

bool triangleTouchesBox(const Triangle& t, const std::array<double, 3>& centre, double half) {
  double v[3][3];
  for (int i = 0; i < 3; ++i)
    for (int a = 0; a < 3; ++a) v[i][a] = double(t.v[i](a)) - centre[a];
  const double e[3][3] = {{v[1][0] - v[0][0], v[1][1] - v[0][1], v[1][2] - v[0][2]},
                          {v[2][0] - v[1][0], v[2][1] - v[1][1], v[2][2] - v[1][2]},
                          {v[0][0] - v[2][0], v[0][1] - v[2][1], v[0][2] - v[2][2]}};
  auto separated = [&](const double axis[3]) {
    const double p0 = dot(v[0], axis), p1 = dot(v[1], axis), p2 = dot(v[2], axis);
    const double r = half * (std::abs(axis[0]) + std::abs(axis[1]) + std::abs(axis[2]));
    return std::min({p0, p1, p2}) > r || std::max({p0, p1, p2}) < -r;
  };
  // The 9 edge cross products, the 3 box face normals, the triangle normal.
  for (int i = 0; i < 3; ++i)
    for (int a = 0; a < 3; ++a) {
      double unit[3] = {0, 0, 0};
      unit[a] = 1.0;
      double axis[3];
      cross(unit, e[i], axis);
      if (separated(axis)) return false;
    }
  for (int a = 0; a < 3; ++a) {
    double unit[3] = {0, 0, 0};
    unit[a] = 1.0;
    if (separated(unit)) return false;
  }
  double normal[3];
  cross(e[0], e[1], normal);
  return !separated(normal);
}

std::uint64_t regionVoxelCount(const AxisBox& region, double resolution) {
  const octomap::OcTree grid(resolution);
  // Beyond OctoMap's 16-bit keys coordToKey's int conversion is undefined (an import may hold such coordinates,
  // with a warning): such a region saturates, more voxels than any limit.
  const double key_reach = 32768.0 * resolution;
  for (int a = 0; a < 3; ++a)
    if (!(std::abs(region.min[a]) < key_reach && std::abs(region.max[a]) < key_reach)) return UINT64_MAX;
  std::uint64_t n = 1;
  for (int a = 0; a < 3; ++a) {
    auto [lo, hi] = centreKeyRange(grid, region.min[a], region.max[a]);
    if (hi < lo) return 0;
    n *= std::uint64_t(hi - lo + 1);
  }
  return n;
}

GroundTruth makeGroundTruth(const TruthSources& sources, const AxisBox& region, double resolution) {
  if (!(resolution > 0.0)) throw std::invalid_argument("ground truth: resolution must be > 0");
  for (int a = 0; a < 3; ++a)
    if (!(region.min[a] <= region.max[a]) || !std::isfinite(region.min[a]) || !std::isfinite(region.max[a]))
      throw std::invalid_argument("ground truth: region min must be <= max and finite on every axis");

  const octomap::OcTree grid(resolution);  // OctoMap's own key arithmetic
  GroundTruth gt;
  gt.resolution = resolution;
  gt.region = region;
  for (int a = 0; a < 3; ++a) {
    auto [lo, hi] = centreKeyRange(grid, region.min[a], region.max[a]);
    gt.region_min_key[a] = octomap::key_type(lo);
    gt.region_max_key[a] = octomap::key_type(std::max(hi, lo - 1));
    if (hi < lo) throw std::invalid_argument("ground truth: the region holds no voxel centre");
  }
  // Counted before any per-voxel allocation (classification and replay allocate per region voxel).
  checkLimit("region: voxels at resolution " + std::to_string(resolution) + " m", gt.regionVoxelCount(),
             limits().region_voxels, "--max-region-voxels");
  forEachTruthVoxel(sources, gt, [&gt](const OcTreeKey& key) { gt.occupied.insert(key); });
  return gt;
}

namespace {

// A triangle flat along an axis lies in one layer of voxels: the one coordToKey puts its points in (visitRange
// tests only that layer). Tested in the layer's mid-plane, a triangle in a voxel face's plane is not lost to the
// rounding of the face test (docs/definitions.md, "Ground truth and evaluation region").
Triangle inLayer(const Triangle& t, const std::array<double, 3>& lo, const std::array<double, 3>& hi,
                 const std::array<double, 3>& centre) {
  Triangle moved = t;
  for (int a = 0; a < 3; ++a)
    if (lo[a] == hi[a])
      for (auto& v : moved.v) v(a) = float(centre[a]);
  return moved;
}

}  // namespace

void forEachTruthVoxel(const TruthSources& sources, const GroundTruth& frame,
                       const std::function<void(const octomap::OcTreeKey&)>& visit) {
  const octomap::OcTree grid(frame.resolution);
  const double half = frame.resolution / 2.0;

  auto visitRange = [&](const std::array<double, 3>& lo, const std::array<double, 3>& hi, auto&& test) {
    int k0[3], k1[3];
    for (int a = 0; a < 3; ++a) {
      k0[a] = std::max<int>(grid.coordToKey(lo[a]), frame.region_min_key[a]);
      k1[a] = std::min<int>(grid.coordToKey(hi[a]), frame.region_max_key[a]);
    }
    for (int x = k0[0]; x <= k1[0]; ++x)
      for (int y = k0[1]; y <= k1[1]; ++y)
        for (int z = k0[2]; z <= k1[2]; ++z) {
          const OcTreeKey key(x, y, z);
          const std::array<double, 3> c = {grid.keyToCoord(key[0]), grid.keyToCoord(key[1]),
                                           grid.keyToCoord(key[2])};
          if (test(c)) visit(key);
        }
  };

  for (const AxisBox& b : sources.boxes)
    visitRange(b.min, b.max, [&](const std::array<double, 3>& c) {
      for (int a = 0; a < 3; ++a)
        if (!(c[a] - half < b.max[a] && c[a] + half > b.min[a])) return false;
      return true;
    });
  for (const Triangle& t : sources.mesh) {
    std::array<double, 3> lo, hi;
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min({t.v[0](a), t.v[1](a), t.v[2](a)});
      hi[a] = std::max({t.v[0](a), t.v[1](a), t.v[2](a)});
    }
    visitRange(lo, hi,
               [&](const std::array<double, 3>& c) { return triangleTouchesBox(inLayer(t, lo, hi, c), c, half); });
  }
  for (const auto& p : sources.points) {
    OcTreeKey key;
    if (grid.coordToKeyChecked(p, key) && frame.inRegion(key)) visit(key);
  }
}

}  // namespace occsweep
