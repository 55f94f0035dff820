// A second, deliberately simple k-NN mapper, written from the paper alone (Miao, Hunter, Georgilas, "An Occupancy
// Mapping Method Based on K-Nearest Neighbours", Sensors 2022: Eq. 2-10 and Algorithm 1) and the decisions of
// docs/design.md ("The k-NN model"), without looking at the library's k-NN code. Test-only: it is the oracle of
// tests/sweeps/test_knn_reference.cpp, never linked into occsweep.
//
// Simple on purpose: brute-force neighbour search over every pair, a std::map from voxel key to log-odds, plain
// loops, one step of Algorithm 1 per block. Only the ray keys come from liboctomap itself (computeRayKeys), as the
// paper's maps are OctoMap's.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <map>
#include <set>
#include <tuple>
#include <vector>

#include <octomap/OcTree.h>

#include "occsweep/methods/knn/knn_parameters.hpp"
#include "occsweep/core/point_cloud_set.hpp"

namespace occsweep::reference {

/// Voxel keys in lexicographic order (OcTreeKey has no operator<).
struct KeyLess {
  bool operator()(const octomap::OcTreeKey& a, const octomap::OcTreeKey& b) const {
    return std::tie(a[0], a[1], a[2]) < std::tie(b[0], b[1], b[2]);
  }
};
using KeySet = std::set<octomap::OcTreeKey, KeyLess>;
/// The map m of Algorithm 1: voxel key -> log-odds, at the finest level. A voxel absent is unknown.
using LogOddsMap = std::map<octomap::OcTreeKey, float, KeyLess>;

/// Eq. 2: l(x) = ln(x / (1 - x)), computed in double and kept as float, as OctoMap stores log-odds.
inline float logOddsEq2(double x) { return static_cast<float>(std::log(x / (1.0 - x))); }

/// Eq. 3 with the clamping of Eq. 5: l <- max(min(l + delta, l_max), l_min). A voxel not yet in m starts at
/// l = 0 (prior 0.5, Section 2).
inline void updateNodeEq5(LogOddsMap& m, const octomap::OcTreeKey& key, float delta, float l_min, float l_max) {
  auto [it, inserted] = m.try_emplace(key, 0.0f);
  const float sum = it->second + delta;
  it->second = std::max(std::min(sum, l_max), l_min);
}

/// Algorithm 1 lines 1-2 (GetInnerPoints): the points within s_c of x_t, distance measured as OctoMap's
/// computeUpdate measures it ((p - origin).norm(), float components), `<= s_c` counting as within.
inline bool isInner(const octomap::point3d& p, const octomap::point3d& origin, double s_c) {
  return (p - origin).norm() <= s_c;
}

/// Algorithm 1 line 5 (GetAverageDistance, Section 3.1): the mean Euclidean distance from z_in[i] to its k nearest
/// *other* points of z_in, by brute force. Fewer than k others: the mean over those there are; none: +inf
/// (docs/design.md). Distances in double from the float coordinates, summed nearest first.
inline double averageDistance(const std::vector<octomap::point3d>& z_in, std::size_t i, int k) {
  std::vector<double> distances;
  for (std::size_t j = 0; j < z_in.size(); ++j) {
    if (j == i) continue;  // itself excluded by index: a duplicate point at distance 0 is a neighbour
    const double dx = double(z_in[j].x()) - double(z_in[i].x());
    const double dy = double(z_in[j].y()) - double(z_in[i].y());
    const double dz = double(z_in[j].z()) - double(z_in[i].z());
    distances.push_back(std::sqrt(dx * dx + dy * dy + dz * dz));
  }
  if (distances.empty()) return std::numeric_limits<double>::infinity();
  std::sort(distances.begin(), distances.end());
  const std::size_t used = std::min<std::size_t>(static_cast<std::size_t>(k), distances.size());
  double sum = 0.0;
  for (std::size_t j = 0; j < used; ++j) sum += distances[j];
  return sum / static_cast<double>(used);
}

/// The points of one scan that lie within s_c (Algorithm 1 line 1), in their order.
inline std::vector<octomap::point3d> innerPointsOf(const Scan& scan, double s_c) {
  std::vector<octomap::point3d> z_in;
  for (const auto& p : scan.points)
    if (isInner(p, scan.origin, s_c)) z_in.push_back(p);
  return z_in;
}

/// Eq. 9 as printed, one s_i at a time (mu_0 = Q_0 = 0); Eq. 10 gives mu and sigma.
struct WelfordEq9 {
  double n = 0, mu = 0, Q = 0;
  void add(double s) {
    n += 1;
    const double mu_prev = mu;
    mu = (n - 1) / n * mu_prev + s / n;
    Q = Q + (s - mu_prev) * (s - mu);
  }
  [[nodiscard]] double sigma() const { return n > 0 ? std::sqrt(Q / n) : 0.0; }  // Eq. 10 (no s_i yet: unused)
};

struct NormalStats {
  double mu = 0, sigma = 0;
};

/// Line 5 for every point of z_in of every scan: s[t][i] is s_i of the i-th inner point of scan t.
using SetDistances = std::vector<std::vector<double>>;

inline SetDistances averageDistances(const PointCloudSet& set, int k, double s_c) {
  SetDistances s;
  for (const auto& scan : set) {
    const auto z_in = innerPointsOf(scan, s_c);
    s.emplace_back();
    for (std::size_t i = 0; i < z_in.size(); ++i) s.back().push_back(averageDistance(z_in, i, k));
  }
  return s;
}

/// mu and sigma (Eq. 8-10) to use for each scan. Batch (the paper, Section 3.2: "all the points within range s_c in
/// a point cloud set"): the values after every s_i of the set, the same for all scans. Online: the values after the
/// s_i of scans 0..t. The s_i enter in scan order then point order; infinite s_i are left out (docs/design.md).
inline std::vector<NormalStats> statsPerScan(const SetDistances& s, StatsMode mode) {
  WelfordEq9 welford;
  std::vector<NormalStats> per_scan;
  for (const auto& scan_s : s) {
    for (double s_i : scan_s)
      if (std::isfinite(s_i)) welford.add(s_i);
    per_scan.push_back({welford.mu, welford.sigma()});
  }
  if (mode == StatsMode::Batch)
    for (auto& stats : per_scan) stats = per_scan.back();
  return per_scan;
}

/// Eq. 6 with F the normal CDF of Eq. 8: p(s) = p_u - F(s) (p_u - p_l). sigma = 0 makes F a right-continuous step
/// at mu, and s = +inf gives F = 1 (docs/design.md).
inline double probabilityEq6(double s, const NormalStats& stats, const KnnParams& params) {
  double F;
  if (std::isinf(s)) F = 1.0;
  else if (stats.sigma == 0.0) F = s >= stats.mu ? 1.0 : 0.0;
  else F = 0.5 * std::erfc(-(s - stats.mu) / (stats.sigma * std::sqrt(2.0)));
  return params.p_u - F * (params.p_u - params.p_l);
}

/// The keys of the ray from origin to end, as liboctomap computes them (origin voxel in, end voxel out). `ray` is
/// scratch space, passed in because an octomap::KeyRay allocates room for 100,000 keys.
inline void addRayKeys(const octomap::OcTree& grid, const octomap::point3d& origin, const octomap::point3d& end,
                       octomap::KeyRay& ray, KeySet& keys) {
  if (grid.computeRayKeys(origin, end, ray)) keys.insert(ray.begin(), ray.end());
}

/// One scan z_t from x_t into m: Algorithm 1, line by line.
inline void algorithm1(LogOddsMap& m, const Scan& scan, const std::vector<double>& s, const NormalStats& stats,
                       const KnnParams& params, const octomap::OcTree& grid) {
  const float l_min = logOddsEq2(params.p_min), l_max = logOddsEq2(params.p_max);
  // Lines 1-2: z_in and z_out.
  std::vector<octomap::point3d> z_in, z_out;
  for (const auto& p : scan.points) (isInner(p, scan.origin, params.map.s_c) ? z_in : z_out).push_back(p);

  // Lines 3-6: m' accumulates l(p(s_i)) per voxel holding points (Eq. 7, first case: sum_j l[p(s_j)]), in float
  // and in point order, as a map of OctoMap's float log-odds would.
  LogOddsMap m_prime;
  for (std::size_t i = 0; i < z_in.size(); ++i)  // s[i] = GetAverageDistance(z_in, P_i, k), line 5
    m_prime[grid.coordToKey(z_in[i])] += logOddsEq2(probabilityEq6(s[i], stats, params));
  // Lines 7-10: each voxel of m' updates m once (Eq. 3). Its sum is clamped to [l_min, l_max] once before the
  // update, as docs/design.md reads line 6's m'.UpdateNode, then Eq. 5 clamps the result.
  for (const auto& [key, sum] : m_prime) updateNodeEq5(m, key, std::max(std::min(sum, l_max), l_min), l_min, l_max);

  // Line 11: m_in, the voxels traversed by rays to z_in points.
  octomap::KeyRay ray;
  KeySet m_in;
  for (const auto& p : z_in) addRayKeys(grid, scan.origin, p, ray, m_in);
  // Lines 12-13: each updated once with l_in = l(p_m). Default variant (docs/design.md, as OctoMap's computeUpdate:
  // occupied wins): a voxel holding an in-range point is not also updated as traversed. Literal: every voxel of m_in.
  const bool literal = params.map.variant == UpdateVariant::Literal;
  for (const auto& key : m_in)
    if (literal || !m_prime.count(key)) updateNodeEq5(m, key, logOddsEq2(params.p_m), l_min, l_max);

  // Line 14: m_out, the voxels traversed by rays to z_out points, cut at s_c as OctoMap's computeUpdate cuts them.
  KeySet m_out;
  for (const auto& p : z_out) {
    const octomap::point3d cut_end = scan.origin + (p - scan.origin).normalized() * static_cast<float>(params.map.s_c);
    addRayKeys(grid, scan.origin, cut_end, ray, m_out);
  }
  // Lines 15-20: those not in m_in are updated once with l_out = l(p'_m) (Eq. 7: "updated with l_in only" when
  // both apply). Default variant: hit voxels are skipped here too.
  for (const auto& key : m_out)
    if (!m_in.count(key) && (literal || !m_prime.count(key)))
      updateNodeEq5(m, key, logOddsEq2(params.p_m_out), l_min, l_max);
}

/// The whole point cloud set, scan after scan (Eq. 3: the map carries over from z_{1:t-1} to z_{1:t}), with the
/// s_i of averageDistances(set, params.k, params.map.s_c).
inline LogOddsMap buildMap(const PointCloudSet& set, const KnnParams& params, const SetDistances& s) {
  const octomap::OcTree grid(params.map.resolution);  // only for OctoMap's keys and ray keys
  const auto stats = statsPerScan(s, params.map.stats);
  LogOddsMap m;
  for (std::size_t t = 0; t < set.size(); ++t) algorithm1(m, set[t], s[t], stats[t], params, grid);
  return m;
}

inline LogOddsMap buildMap(const PointCloudSet& set, const KnnParams& params) {
  return buildMap(set, params, averageDistances(set, params.k, params.map.s_c));
}

}  // namespace occsweep::reference
