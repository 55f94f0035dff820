// The voxel filter and the naive approach against brute force, the point cloud grid.
#include <map>

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "occsweep/core/splitmix64.hpp"
#include "occsweep/eval/naive.hpp"
#include "occsweep/stereo/cloud.hpp"
#include "occsweep/stereo/pointcloud_grid.hpp"
#include "occsweep/sweeps/grid.hpp"

using namespace occsweep;
using namespace occsweep::stereo;

TEST_CASE("Voxel filter: one centroid per voxel, as brute force, whatever the input order", "[stereo][cloud]") {
  for (std::uint64_t seed = 1; seed <= 30; ++seed) {
    SplitMix64 rng(seed);
    std::vector<Eigen::Vector3d> pts;
    const int n = 1 + int(rng.below(3000));
    for (int i = 0; i < n; ++i) pts.emplace_back(rng.uniform() * 2 - 1, rng.uniform() * 2 - 1, rng.uniform() * 0.5);
    std::map<std::array<long, 3>, std::pair<Eigen::Vector3d, int>> brute;
    for (const auto& p : pts) {
      auto& [sum, count] = brute[{long(std::floor(p.z() / 0.1)), long(std::floor(p.y() / 0.1)), long(std::floor(p.x() / 0.1))}];
      if (count == 0) sum.setZero();
      sum += p, ++count;
    }
    const auto filtered = voxelFilter(pts, 0.1);
    REQUIRE(filtered.size() == brute.size());
    std::size_t i = 0;
    for (const auto& [key, sc] : brute) {  // std::map order = (z, y, x) ascending, the documented order
      const Eigen::Vector3d c = sc.first / sc.second;
      CHECK(filtered[i].x() == Approx(c.x()).margin(1e-6));
      CHECK(filtered[i].y() == Approx(c.y()).margin(1e-6));
      CHECK(filtered[i].z() == Approx(c.z()).margin(1e-6));
      ++i;
    }
    std::vector<Eigen::Vector3d> reversed(pts.rbegin(), pts.rend());
    const auto again = voxelFilter(reversed, 0.1);
    REQUIRE(again.size() == filtered.size());
    for (std::size_t k = 0; k < again.size(); ++k) CHECK((again[k] - filtered[k]).norm() < 1e-6f);
  }
}

TEST_CASE("Naive approach: counts equal a brute-force pass over every region voxel", "[stereo][naive]") {
  for (std::uint64_t seed = 1; seed <= 25; ++seed) {
    SplitMix64 rng(seed);
    TruthSources src;
    for (int b = 0; b < 3; ++b) {
      const double x = rng.uniform() * 2 - 1, y = rng.uniform() * 2 - 1;
      src.boxes.push_back(AxisBox{{x, y, 0.0}, {x + 0.1 + rng.uniform() * 0.6, y + 0.1 + rng.uniform() * 0.6, 0.5}});
    }
    const AxisBox region{{-1.2, -1.1, 0.1}, {1.3, 1.25, 0.9}};
    const GroundTruth gt = makeGroundTruth(src, region, 0.1);
    PointCloudSet set(3);
    for (auto& scan : set)
      for (int i = 0; i < 400; ++i)
        scan.points.emplace_back(float(rng.uniform() * 3.4 - 1.7), float(rng.uniform() * 3.4 - 1.7), float(rng.uniform() * 1.2 - 0.1));
    const octomap::OcTree grid(0.1);
    octomap::KeySet hit;
    for (const auto& scan : set)
      for (const auto& p : scan.points) hit.insert(grid.coordToKey(p));
    ConfusionCounts brute;
    for (int x = gt.region_min_key[0]; x <= gt.region_max_key[0]; ++x)
      for (int y = gt.region_min_key[1]; y <= gt.region_max_key[1]; ++y)
        for (int z = gt.region_min_key[2]; z <= gt.region_max_key[2]; ++z) {
          const octomap::OcTreeKey k(x, y, z);
          const bool truth = gt.occupied.count(k), predicted = hit.count(k);
          (truth ? (predicted ? brute.tp : brute.fn) : (predicted ? brute.fp : brute.tn)) += 1;
        }
    CHECK(naiveConfusion(set, gt) == brute);
  }
}

TEST_CASE("The point cloud grid: 1,600 combinations in canonical order, even subsets", "[stereo][grid]") {
  const PointCloudGrid g = loadPointCloudGrid(resolveGridPath("pointcloud"));
  REQUIRE(g.size() == 1600);
  std::uint64_t id = 0;
  for (int b : {3, 5, 7, 9, 11})
    for (int u : {5, 10, 15, 20, 25})
      for (int sw : {0, 50, 100, 200})
        for (int sr : {1, 2, 4, 8})
          for (int d : {-1, 0, 1, 2}) {
            const SgbmParams p = g.at(id++);
            REQUIRE(p == SgbmParams{b, u, sw, sr, d});
            REQUIRE(p.p1() == 8 * b * b);
            REQUIRE(p.p2() == 32 * b * b);
          }
  CHECK_THROWS(g.at(1600));
  CHECK(evenSubset(1600, 3) == std::vector<std::uint64_t>{0, 800, 1599});
  for (std::uint64_t n = 2; n <= 40; ++n) {
    const auto s = evenSubset(1600, n);
    REQUIRE(s.size() == n);
    CHECK(s.front() == 0);
    CHECK(s.back() == 1599);
    CHECK(std::adjacent_find(s.begin(), s.end(), std::greater_equal<>()) == s.end());  // strictly increasing
  }
  CHECK(evenSubset(5, 9).size() == 5);
}

TEST_CASE("Bad point cloud grids are refused with the key named", "[stereo][grid]") {
  auto good = [] {
    return nlohmann::json{{"name", "t"}, {"kind", "stereo-sgbm"},
                          {"parameters", {{"blockSize", {3, 5}}, {"uniquenessRatio", {5}}, {"speckleWindowSize", {0}},
                                          {"speckleRange", {1}}, {"disp12MaxDiff", {-1}}}}};
  };
  CHECK(parsePointCloudGrid(good(), "g.json").size() == 2);
  auto j = good();
  j["parameters"]["blockSize"] = {4};
  CHECK_THROWS_WITH(parsePointCloudGrid(j, "g.json"), Catch::Contains("g.json") && Catch::Contains("blockSize"));
  j = good();
  j["parameters"]["blockSize"] = {3, 3};
  CHECK_THROWS_WITH(parsePointCloudGrid(j, "g.json"), Catch::Contains("repeated"));
  j = good();
  j["parameters"].erase("speckleRange");
  CHECK_THROWS_WITH(parsePointCloudGrid(j, "g.json"), Catch::Contains("speckleRange") && Catch::Contains("missing"));
  j = good();
  j["parameters"]["P1"] = {8};
  CHECK_THROWS_WITH(parsePointCloudGrid(j, "g.json"), Catch::Contains("P1"));
  CHECK_THROWS_WITH(parseSgbmParams("blockSize=6"), Catch::Contains("blockSize"));
  CHECK_THROWS_WITH(parseSgbmParams("blocksize=5"), Catch::Contains("unknown key"));
  CHECK(parseSgbmParams("blockSize=7,disp12MaxDiff=-1") == SgbmParams{7, 10, 100, 2, -1});
}
