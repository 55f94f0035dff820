// Our ray traversal against liboctomap's computeRayKeys: the same keys in the same order, on random rays of every
// kind (long and short, axis-aligned, ending on voxel borders, at other resolutions).
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

TEST_CASE("traverseRay refuses ends outside the octree like liboctomap") {
  octomap::OcTree grid(0.1);
  int visited = 0;
  CHECK_FALSE(traverseRay(grid, {0, 0, 0}, {1e5f, 0, 0}, [&](const octomap::OcTreeKey&) { ++visited; }));
  CHECK(visited == 0);
  CHECK(traverseRay(grid, {0.01f, 0.01f, 0.01f}, {0.02f, 0.02f, 0.02f}, [&](const octomap::OcTreeKey&) { ++visited; }));
  CHECK(visited == 0);  // one voxel: nothing
}
