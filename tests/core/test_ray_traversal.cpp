// Our ray traversal against liboctomap's computeRayKeys: the same keys in the same order, on random rays of every
// kind (long and short, axis-aligned, ending on voxel borders, at other resolutions); and the traversal that skips
// to a window against the full traversal's keys in that window.
#include <catch2/catch.hpp>

#include <vector>

#include "occsweep/core/ray_traversal.hpp"
#include "test_helpers.hpp"

using namespace occsweep;

TEST_CASE("traverseRay visits exactly liboctomap's ray keys") {
  std::size_t rays = 0, keys = 0;
  for (double resolution : {0.1, 0.05, 0.25, 0.13}) {
    octomap::OcTree grid(resolution);
    SplitMix64 rng(std::uint64_t(resolution * 1000));
    octomap::KeyRay reference;
    std::vector<octomap::OcTreeKey> ours;
    for (int i = 0; i < 250000; ++i) {
      auto coord = [&](double extent) {
        switch (rng.below(4)) {
          case 0: return float(std::round((rng.uniform() - 0.5) * extent / resolution) * resolution);  // on a border
          case 1: return float(rng.uniform() < 0.5 ? 0.0 : resolution * 0.5);
          default: return float((rng.uniform() - 0.5) * extent);
        }
      };
      const double extent = rng.below(2) ? 2.0 : 20.0;
      const octomap::point3d a(coord(extent), coord(extent), coord(extent));
      octomap::point3d b(coord(extent), coord(extent), coord(extent));
      if (rng.below(8) == 0) b = octomap::point3d(a.x(), b.y(), a.z());  // axis-aligned
      ours.clear();
      const bool ok = traverseRay(grid, a, b, [&](const octomap::OcTreeKey& k) { ours.push_back(k); });
      const bool ok_ref = grid.computeRayKeys(a, b, reference);
      REQUIRE(ok == ok_ref);
      REQUIRE(ours.size() == reference.size());
      for (std::size_t j = 0; j < ours.size(); ++j) REQUIRE(ours[j] == *(reference.begin() + long(j)));
      ++rays;
      keys += ours.size();
    }
  }
  CHECK(rays == 1000000);
  CHECK(keys > 10000000);
}

namespace {

// A coordinate of a random ray end: on a voxel border (ties between the axes' borders), on 0 or a voxel centre, or
// anywhere.
float rayCoordinate(SplitMix64& rng, double extent, double resolution) {
  switch (rng.below(4)) {
    case 0: return float(std::round((rng.uniform() - 0.5) * extent / resolution) * resolution);
    case 1: return float(rng.uniform() < 0.5 ? 0.0 : resolution * 0.5);
    default: return float((rng.uniform() - 0.5) * extent);
  }
}

// A random window near the keys between a and b: holding a, holding b, crossed, missed, one voxel thick, one voxel.
KeyWindow windowNear(SplitMix64& rng, const octomap::OcTree& grid, const octomap::point3d& a, const octomap::point3d& b) {
  const octomap::OcTreeKey ka = grid.coordToKey(a), kb = grid.coordToKey(b);
  KeyWindow w;
  for (int i = 0; i < 3; ++i) {
    const int lo = std::min(ka[i], kb[i]) - 3, hi = std::max(ka[i], kb[i]) + 3;
    int x = lo + int(rng.below(std::uint64_t(hi - lo + 1))), y = lo + int(rng.below(std::uint64_t(hi - lo + 1)));
    if (rng.below(6) == 0) y = x;  // one voxel thick
    w.lo[i] = std::max(0, std::min(x, y));
    w.hi[i] = std::min(65535, std::max(x, y));
  }
  return w;
}

}  // namespace

TEST_CASE("traverseRayInWindow visits exactly the keys of traverseRay that lie in the window, in order") {
  std::size_t rays = 0, skipped = 0, keys = 0;
  for (double resolution : {0.1, 0.05, 0.25, 0.13}) {
    octomap::OcTree grid(resolution);
    SplitMix64 rng(std::uint64_t(resolution * 1000) + 7);
    std::vector<octomap::OcTreeKey> all, in_window, ours;
    for (int i = 0; i < 250000; ++i) {
      const double extent = rng.below(2) ? 2.0 : 20.0;
      auto point = [&] {
        return octomap::point3d(rayCoordinate(rng, extent, resolution), rayCoordinate(rng, extent, resolution),
                                rayCoordinate(rng, extent, resolution));
      };
      octomap::point3d a = point();
      octomap::point3d b = point();
      if (rng.below(8) == 0) b = octomap::point3d(a.x(), b.y(), a.z());  // axis-aligned
      if (rng.below(8) == 0) b = octomap::point3d(b.x(), b.y(), a.z());  // in a plane
      // Diagonal: two or three axes with equal coordinates step on equal borders, a tie at every crossing.
      const std::uint64_t diagonal = rng.below(6);
      if (diagonal < 3) {
        const int i = int(diagonal), j = (i + 1) % 3;
        a(j) = a(i), b(j) = b(i);
        if (rng.below(3) == 0) a((j + 1) % 3) = a(i), b((j + 1) % 3) = b(i);
      }
      const KeyWindow w = windowNear(rng, grid, a, b);
      all.clear(), in_window.clear(), ours.clear();
      const bool ok = traverseRay(grid, a, b, [&](const octomap::OcTreeKey& k) { all.push_back(k); });
      for (const auto& k : all)
        if (w.contains(k)) in_window.push_back(k);
      bool indices_match = true;
      const bool ok_window = traverseRayInWindow(grid, a, b, w, [&](std::uint64_t index) {
        ours.push_back(w.key(index));
        indices_match = indices_match && index < w.volume() && index == w.index(w.key(index));
      });
      REQUIRE(indices_match);
      REQUIRE(ok_window == ok);
      REQUIRE(ours == in_window);
      ++rays;
      keys += ours.size();
      skipped += !in_window.empty() && !w.contains(all.front());  // the origin's key outside: keys skipped
    }
  }
  CHECK(rays == 1000000);
  CHECK(skipped > 100000);  // the skip itself was exercised, not only windows holding the origin
  CHECK(keys > 1000000);
}

TEST_CASE("traverseRay refuses ends outside the octree like liboctomap") {
  octomap::OcTree grid(0.1);
  int visited = 0;
  CHECK_FALSE(traverseRay(grid, {0, 0, 0}, {1e5f, 0, 0}, [&](const octomap::OcTreeKey&) { ++visited; }));
  CHECK(visited == 0);
  CHECK(traverseRay(grid, {0.01f, 0.01f, 0.01f}, {0.02f, 0.02f, 0.02f}, [&](const octomap::OcTreeKey&) { ++visited; }));
  CHECK(visited == 0);  // one voxel: nothing
}
