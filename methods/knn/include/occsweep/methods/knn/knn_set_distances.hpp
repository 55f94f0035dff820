// The parts of the k-NN model that depend only on the points, k and s_c: the z_in / z_out split, s_i,
// and mu, sigma (Eq. 9-10). Computed once and shared by every probability setting of a sweep.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "knn_average_distance.hpp"
#include "occsweep/core/point_cloud_set.hpp"
#include "occsweep/core/scan_executor.hpp"
#include "occsweep/core/welford.hpp"

namespace occsweep {

/// One scan: which points are in z_in (range <= s_c) and their s_i.
struct KnnScanDistances {
  std::vector<std::uint32_t> inner;  ///< indices into Scan::points of z_in, in point order
  std::vector<double> s;             ///< s_i of each z_in point, same order; +inf with no neighbour
  double online_mu = 0.0;            ///< Welford mean over every finite s_i up to and including this scan
  double online_sigma = 0.0;         ///< and its deviation sqrt(Q/n)
};

/// A whole point cloud set.
struct KnnSetDistances {
  int k = 0;
  double s_c = 0.0;
  std::vector<KnnScanDistances> scans;
  double mu = 0.0;     ///< Eq. 10 over every finite s_i of the set (the paper's first pass)
  double sigma = 0.0;
};

/// z_in split and s_i for every scan, then Welford over the s_i in scan and point order. Infinite s_i (a point
/// alone within s_c) are left out of mu and sigma, which they would make infinite; F(+inf) = 1 still applies.
[[nodiscard]] KnnSetDistances computeKnnDistances(const PointCloudSet& set, int k, double s_c);

/// One scan's z_in and s_i (no statistics): the part that scans can compute independently, in parallel.
[[nodiscard]] KnnScanDistances scanKnnDistances(const Scan& scan, int k, double s_c);

/// computeKnnDistances with the scans' searches on `executor`; the statistics are accumulated in scan order
/// afterwards, so the result is identical.
[[nodiscard]] KnnSetDistances computeKnnDistances(const PointCloudSet& set, int k, double s_c,
                                                  const ScanExecutor& executor);

/// Welford over the scans' s_i in scan and point order: fills online_mu/sigma per scan and the set's mu, sigma.
void accumulateStatistics(KnnSetDistances& d);

// ---------------------------------------------------------------------------------------------------------

inline KnnScanDistances scanKnnDistances(const Scan& scan, int k, double s_c) {
  KnnScanDistances d;
  d.inner = innerPoints(scan, s_c);
  std::vector<octomap::point3d> inner_points;
  inner_points.reserve(d.inner.size());
  for (auto i : d.inner) inner_points.push_back(scan.points[i]);
  d.s = averageKnnDistances(inner_points, k);
  return d;
}

inline void accumulateStatistics(KnnSetDistances& out) {
  Welford welford;
  for (KnnScanDistances& d : out.scans) {
    for (double s : d.s)
      if (std::isfinite(s)) welford.add(s);
    d.online_mu = welford.mean();
    d.online_sigma = welford.sigma();
  }
  out.mu = welford.mean();
  out.sigma = welford.sigma();
}

inline KnnSetDistances computeKnnDistances(const PointCloudSet& set, int k, double s_c, const ScanExecutor& executor) {
  KnnSetDistances out;
  out.k = k;
  out.s_c = s_c;
  out.scans.resize(set.size());
  executor.run(set.size(), [&](std::size_t t) { out.scans[t] = scanKnnDistances(set[t], k, s_c); });
  accumulateStatistics(out);
  return out;
}

inline KnnSetDistances computeKnnDistances(const PointCloudSet& set, int k, double s_c) {
  return computeKnnDistances(set, k, s_c, ScanExecutor{});
}

}  // namespace occsweep
