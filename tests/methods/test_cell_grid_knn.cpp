// The grid-of-cells k-NN search (cell_grid_knn.hpp) against brute force, bit for bit: dense and sparse clouds
// over 20 seeds, duplicates, ties on a lattice, outliers far from dense cells, isolated points whose nearest lies
// rings of cells away, k above the points, one point; and one search for several k against a search per k.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>

#include "occsweep/methods/knn/knn_average_distance.hpp"
#include "occsweep/core/limits.hpp"
#include "test_helpers.hpp"

using namespace occsweep;

namespace {

// Equal as doubles and in every bit (+inf included): what "bit for bit" claims.
bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

void requireBitIdentical(const std::vector<double>& grid, const std::vector<double>& brute, const std::string& what) {
  REQUIRE(grid.size() == brute.size());
  for (std::size_t i = 0; i < grid.size(); ++i) {
    INFO(what << " point " << i << " grid " << grid[i] << " brute force " << brute[i]);
    REQUIRE(sameBits(grid[i], brute[i]));
  }
}

// A range scan's kind of cloud: a bumpy surface sampled densely, with some points on a second surface behind.
std::vector<octomap::point3d> denseSurface(SplitMix64& rng, std::size_t n) {
  std::vector<octomap::point3d> pts;
  for (std::size_t i = 0; i < n; ++i) {
    const double u = rng.uniform() * 2.0, v = rng.uniform() * 1.5;
    const double depth = rng.below(5) == 0 ? 3.0 : 2.0 + 0.05 * std::sin(7 * u) * std::cos(5 * v);
    pts.emplace_back(float(u), float(v), float(depth + 0.002 * rng.gaussian()));
  }
  return pts;
}

void addDuplicatesAndOutliers(SplitMix64& rng, std::vector<octomap::point3d>& pts) {
  const std::size_t n = pts.size();
  for (std::size_t d = 0; d < n / 10; ++d) pts.push_back(pts[rng.below(pts.size())]);
  for (int o = 0; o < 3; ++o)  // far from everything: many empty rings, then reading all points
    pts.emplace_back(float(20 + 30 * rng.uniform()), float(-10 * rng.uniform()), float(5 * rng.uniform()));
}

}  // namespace

TEST_CASE("the cell-grid k-NN search equals brute force bit for bit on dense and sparse clouds, 20 seeds") {
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    SplitMix64 rng(seed);
    auto dense = denseSurface(rng, 1500 + rng.below(1500));
    auto sparse = test::randomCloud(rng, 1 + rng.below(400), 2.0);
    addDuplicatesAndOutliers(rng, dense);
    addDuplicatesAndOutliers(rng, sparse);
    for (int k : {1, 2 + int(rng.below(6)), 8 + int(rng.below(12))}) {
      INFO("seed " << seed << " k " << k);
      requireBitIdentical(averageKnnDistances(dense, k), averageKnnDistancesBruteForce(dense, k), "dense");
      requireBitIdentical(averageKnnDistances(sparse, k), averageKnnDistancesBruteForce(sparse, k), "sparse");
    }
  }
}

TEST_CASE("isolated points around a dense cluster find their nearest rings away in every direction, 20 seeds") {
  // The cluster sizes the cells small; each isolated point's nearest lies some rings of cells away, in any
  // direction, so the ring search's pruning of planes, rows and cells by their gaps decides the result.
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    SplitMix64 rng(300 + seed);
    std::vector<octomap::point3d> pts;
    for (int i = 0; i < 2000; ++i)
      pts.emplace_back(float(0.2 * rng.uniform()), float(0.2 * rng.uniform()), float(0.2 * rng.uniform()));
    const auto around = [&] { return float(-1.5 + 3 * rng.uniform()); };
    for (int i = 0; i < 300; ++i) pts.emplace_back(around(), around(), around());
    for (int k : {1, 2 + int(rng.below(4))})
      requireBitIdentical(averageKnnDistances(pts, k), averageKnnDistancesBruteForce(pts, k),
                          "seed " + std::to_string(seed) + " k " + std::to_string(k));
  }
}

TEST_CASE("one point's search returns the k smallest squared distances to the others, ascending") {
  SplitMix64 rng(7);
  auto pts = denseSurface(rng, 800);
  addDuplicatesAndOutliers(rng, pts);
  const int k = 6;
  const CellGridKnn grid(pts, k);
  std::vector<double> nearest, all;
  for (std::size_t i = 0; i < pts.size(); i += 7) {
    grid.nearestOtherSquaredDistances(i, k, nearest);
    all.clear();
    for (std::size_t j = 0; j < pts.size(); ++j)
      if (j != i) all.push_back(squaredDistance(pts[i], pts[j]));
    std::sort(all.begin(), all.end());
    all.resize(k);
    INFO("point " << i);
    REQUIRE(nearest == all);
  }
}

TEST_CASE("ties on a lattice: whichever equally distant points are taken, s_i equals brute force bit for bit") {
  // 6 neighbours at one spacing, 12 at sqrt(2) and 8 at sqrt(3) times it: k inside and at the edges of each
  // shell of ties. Float lattice coordinates make some "equal" distances differ in the last bits: the sum must
  // still follow the exact double order.
  std::vector<octomap::point3d> lattice;
  for (int x = 0; x < 9; ++x)
    for (int y = 0; y < 9; ++y)
      for (int z = 0; z < 9; ++z) lattice.emplace_back(0.1f * float(x), 0.1f * float(y), 0.1f * float(z) + 3.0f);
  for (int k : {1, 3, 6, 7, 12, 18, 19, 26, 27, 40})
    requireBitIdentical(averageKnnDistances(lattice, k), averageKnnDistancesBruteForce(lattice, k),
                        "lattice k " + std::to_string(k));
}

TEST_CASE("k above the other points, one point, two points, and every point the same") {
  const std::vector<octomap::point3d> three = {{0, 0, 0}, {3, 0, 0}, {0, 4, 0}};
  const auto s = averageKnnDistances(three, 5);  // only two others each: their mean
  CHECK(s[0] == (3.0 + 4.0) / 2);
  CHECK(s[1] == (3.0 + 5.0) / 2);
  CHECK(s[2] == (4.0 + 5.0) / 2);
  CHECK(std::isinf(averageKnnDistances({{1, 2, 3}}, 3)[0]));  // none: +inf
  CHECK(averageKnnDistances({{1, 2, 3}, {1, 2, 5}}, 4) == std::vector<double>{2.0, 2.0});
  const std::vector<octomap::point3d> same(50, octomap::point3d(1.5f, -2.0f, 0.25f));
  CHECK(averageKnnDistances(same, 3) == std::vector<double>(50, 0.0));  // duplicates count, at 0
  CHECK(std::isinf(averageKnnDistances(three, 0)[0]));
}

TEST_CASE("one search for several k equals a search per k, bit for bit") {
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    SplitMix64 rng(100 + seed);
    auto pts = seed % 2 ? denseSurface(rng, 1000 + rng.below(1000)) : test::randomCloud(rng, 1 + rng.below(300), 2.0);
    addDuplicatesAndOutliers(rng, pts);
    const std::vector<int> ks = {7, 1, 3, 5, 12};
    const auto shared = averageKnnDistancesForEachK(pts, ks);
    REQUIRE(shared.size() == ks.size());
    for (std::size_t m = 0; m < ks.size(); ++m)
      requireBitIdentical(shared[m], averageKnnDistances(pts, ks[m]),
                          "seed " + std::to_string(seed) + " k " + std::to_string(ks[m]));
  }
}

TEST_CASE("the grid search and the former k-d tree give the same s_i on random clouds") {
  // They rank differently (float squared distances in the k-d tree), so equal only up to last-bit rounding
  // where two neighbours' float distances tie or swap; the golden results hold both (docs/performance.md).
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    SplitMix64 rng(200 + seed);
    auto pts = denseSurface(rng, 2000);
    const int k = 1 + int(rng.below(9));
    const auto grid = averageKnnDistances(pts, k), tree = averageKnnDistancesKdTree(pts, k);
    REQUIRE(grid.size() == tree.size());
    for (std::size_t i = 0; i < grid.size(); ++i) {
      INFO("seed " << seed << " point " << i << " k " << k);
      REQUIRE(grid[i] == Approx(tree[i]).epsilon(1e-12));
    }
  }
}

TEST_CASE("k past the sorted array's 128, up to and past the cloud's size, equals brute force bit for bit") {
  // Beyond 128 the k nearest are gathered and cut back by nth_element (NearestSoFar): the cut's bound prunes
  // cells and rings, and ties at it must still give the exact k smallest.
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    SplitMix64 rng(400 + seed);
    auto pts = seed % 2 ? denseSurface(rng, 500 + rng.below(700)) : test::randomCloud(rng, 150 + rng.below(400), 2.0);
    addDuplicatesAndOutliers(rng, pts);
    const int n = int(pts.size());
    for (int k : {129, 130 + int(rng.below(300)), n / 2, n - 2, n - 1, n, 100000}) {
      INFO("seed " << seed << " n " << n << " k " << k);
      requireBitIdentical(averageKnnDistances(pts, k), averageKnnDistancesBruteForce(pts, k), "large k");
    }
  }
  std::vector<octomap::point3d> lattice;  // shells of equal distances around every point
  for (int x = 0; x < 9; ++x)
    for (int y = 0; y < 9; ++y)
      for (int z = 0; z < 9; ++z) lattice.emplace_back(0.1f * float(x), 0.1f * float(y), 0.1f * float(z) + 3.0f);
  for (int k : {129, 200, 400, 727, 728, 1000})
    requireBitIdentical(averageKnnDistances(lattice, k), averageKnnDistancesBruteForce(lattice, k),
                        "lattice k " + std::to_string(k));
}

TEST_CASE("k-NN refuses more neighbour distances than the limit before searching, n x min(k, n - 1) of them") {
  SplitMix64 rng(5);
  const auto pts = test::randomCloud(rng, 1000, 2.0);
  const std::uint64_t saved = limits().neighbour_distances;
  limits().neighbour_distances = 1000 * 999;  // k capped at the 999 others
  CHECK(averageKnnDistances(pts, 100000) == averageKnnDistancesBruteForce(pts, 100000));
  limits().neighbour_distances = 1000 * 999 - 1;
  std::string message;
  try {
    (void)averageKnnDistances(pts, 100000);
  } catch (const LimitError& e) {
    message = e.what();
  }
  limits().neighbour_distances = saved;
  INFO(message);
  for (const char* word : {"knn: k 100000 on the 1000 points", "999000 is more than the limit of 998999",
                           "--max-neighbour-distances"})
    CHECK(message.find(word) != std::string::npos);
}
