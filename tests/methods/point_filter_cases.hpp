// The seeded clouds and settings on which test_point_filters (brute force) and test_point_filters_pcl (PCL itself)
// check core/point_filters.hpp: clusters with outliers, lattices with exact ties and neighbours exactly at the
// radius, heavy duplicates, clouds with fewer than mean_k + 1 points (empty and single ones included).
#pragma once

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <octomap/octomap_types.h>

#include "occsweep/core/splitmix64.hpp"

namespace occsweep::test {

inline constexpr std::uint64_t kFilterSeeds = 200;
/// std_mul from -1 to 5 and 1e9 (nothing removed); 0 puts the threshold at the mean.
inline const std::vector<double> kStdMuls = {-1.0, -0.5, 0.0, 0.3, 1.0, 2.0, 3.0, 5.0, 1e9};
inline const std::vector<int> kMinNeighbours = {0, 1, 2, 5};

struct FilterCase {
  std::string kind;
  std::vector<octomap::point3d> points;
  int mean_k = 1;                // 1..10
  std::vector<double> radii;     // the first is the lattice spacing for lattices
};

inline std::vector<octomap::point3d> clustersWithOutliers(SplitMix64& rng) {
  std::vector<octomap::point3d> pts;
  const std::size_t clusters = 1 + rng.below(4);
  for (std::size_t c = 0; c < clusters; ++c) {
    const double cx = rng.uniform() * 10, cy = rng.uniform() * 10, cz = rng.uniform() * 2;
    const double spread = 0.02 + rng.uniform() * 0.2;
    for (std::size_t i = 0, n = 20 + rng.below(120); i < n; ++i)
      pts.emplace_back(float(cx + spread * rng.gaussian()), float(cy + spread * rng.gaussian()),
                       float(cz + spread * rng.gaussian()));
  }
  for (std::size_t i = 0, n = rng.below(20); i < n; ++i)
    pts.emplace_back(float(rng.uniform() * 12 - 1), float(rng.uniform() * 12 - 1), float(rng.uniform() * 4 - 1));
  return pts;
}

/// A lattice of spacing `spacing` (coordinates i * spacing in float), some nodes left out: every neighbour of a
/// node is at one of a few equal distances, the nearest ones at the spacing itself.
inline std::vector<octomap::point3d> lattice(SplitMix64& rng, float spacing) {
  std::vector<octomap::point3d> pts;
  const int nx = 2 + int(rng.below(6)), ny = 2 + int(rng.below(6)), nz = 1 + int(rng.below(4));
  const float ox = float(rng.below(5)) * spacing;
  for (int x = 0; x < nx; ++x)
    for (int y = 0; y < ny; ++y)
      for (int z = 0; z < nz; ++z)
        if (rng.below(8) != 0) pts.emplace_back(ox + float(x) * spacing, float(y) * spacing, float(z) * spacing);
  return pts;
}

/// A few distinct points, each repeated: zero distances everywhere.
inline std::vector<octomap::point3d> duplicates(SplitMix64& rng) {
  std::vector<octomap::point3d> distinct;
  for (std::size_t i = 0, n = 1 + rng.below(6); i < n; ++i)
    distinct.emplace_back(float(rng.uniform()), float(rng.uniform()), float(rng.uniform()));
  std::vector<octomap::point3d> pts;
  for (std::size_t i = 0, n = 1 + rng.below(40); i < n; ++i) pts.push_back(distinct[rng.below(distinct.size())]);
  return pts;
}

inline void addDuplicates(SplitMix64& rng, std::vector<octomap::point3d>& pts) {
  for (std::size_t i = 0, n = pts.size() / 10; i < n && !pts.empty(); ++i) pts.push_back(pts[rng.below(pts.size())]);
}

/// Seed s picks one of six kinds in turn, mean_k = 1 + s % 10.
inline FilterCase filterCase(std::uint64_t seed) {
  SplitMix64 rng(seed * 7919 + 17);
  FilterCase c;
  c.mean_k = 1 + int(seed % 10);
  const float spacings[] = {0.1f, 0.25f, 0.3f, 1.0f, 0.07f};
  switch (seed % 6) {
    case 0:
      c.kind = "clusters+outliers";
      c.points = clustersWithOutliers(rng);
      addDuplicates(rng, c.points);
      c.radii = {0.05, 0.2, 0.5};
      break;
    case 1:
    case 5: {
      const float s = spacings[rng.below(5)];
      c.kind = "lattice spacing " + std::to_string(s);
      c.points = lattice(rng, s);
      if (seed % 6 == 5) addDuplicates(rng, c.points);
      c.radii = {double(s), double(s) * std::sqrt(2.0), double(std::sqrt(2.0f) * s), 2.0 * s};
      break;
    }
    case 2:
      c.kind = "duplicates";
      c.points = duplicates(rng);
      c.radii = {1e-3, 0.5, 2.0};
      break;
    case 3:
      c.kind = "fewer than mean_k + 1 points";
      for (std::size_t i = 0, n = rng.below(std::uint64_t(c.mean_k) + 2); i < n; ++i)
        c.points.emplace_back(float(rng.uniform()), float(rng.uniform()), float(rng.uniform()));
      c.radii = {0.3, 1.0, 2.0};
      break;
    default:
      c.kind = "uniform";
      for (std::size_t i = 0, n = 1 + rng.below(500); i < n; ++i)
        c.points.emplace_back(float(rng.uniform() * 4), float(rng.uniform() * 4), float(rng.uniform()));
      c.radii = {0.1, 0.25, 0.6};
      break;
  }
  return c;
}

}  // namespace occsweep::test
