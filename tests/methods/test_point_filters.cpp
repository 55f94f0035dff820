// core/point_filters.hpp against a brute-force oracle written from PCL 1.13's source (O(n^2), no k-d tree), on the
// seeded clouds of point_filter_cases.hpp, plus hand-computed values. test_point_filters_pcl compares with PCL
// itself where it is installed. Line numbers: PCL 1.13.0, /usr/include/pcl-1.13/pcl/.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "methods/point_filter_cases.hpp"
#include "occsweep/core/limits.hpp"
#include "occsweep/methods/outlier_filters/point_filters.hpp"

using namespace occsweep;
using octomap::point3d;

namespace {

/// FLANN's L2_Simple<float> written out again (flann/algorithms/dist.h: diff = *a++ - *b++; result += diff*diff).
float flannL2(const point3d& a, const point3d& b) {
  const float dx = a.x() - b.x(), dy = a.y() - b.y(), dz = a.z() - b.z();
  float r = 0.0f;
  r += dx * dx;
  r += dy * dy;
  r += dz * dz;
  return r;
}

/// PCL's nn_dists after nearestKSearch(i, k): the k smallest squared distances to all points (i itself at 0),
/// sorted, k clamped to the cloud size (kdtree_flann.hpp:243-247), then padded with the zeros of the buffer PCL
/// allocated with k entries (statistical_outlier_removal.hpp:64) and reads past the clamped size (:92-93).
std::vector<float> pclNnDists(const std::vector<point3d>& pts, std::size_t i, std::size_t k, bool pad) {
  std::vector<float> d;
  for (const auto& p : pts) d.push_back(flannL2(pts[i], p));
  std::sort(d.begin(), d.end());
  d.resize(std::min(d.size(), k));
  if (pad) d.resize(k, 0.0f);
  return d;
}

/// StatisticalOutlierRemoval<PointT>::applyFilterIndices (statistical_outlier_removal.hpp:49-131), negative_ off,
/// every point finite: the whole of PCL's arithmetic, kept indices in input order.
struct SorOracle {
  std::vector<float> distances;
  double mean = 0, stddev = 0;
  std::vector<std::uint32_t> kept(double std_mul) const {
    const double distance_threshold = mean + std_mul * stddev;                                // :110
    std::vector<std::uint32_t> out;
    for (std::size_t i = 0; i < distances.size(); ++i)
      if (!(distances[i] > distance_threshold)) out.push_back(std::uint32_t(i));  // :117
    return out;
  }
};

SorOracle sorOracle(const std::vector<point3d>& pts, int mean_k) {
  SorOracle o;
  const int searcher_k = mean_k + 1;  // :62
  o.distances.resize(pts.size());
  int valid_distances = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const auto nn_dists = pclNnDists(pts, i, std::size_t(searcher_k), true);
    double dist_sum = 0.0;
    for (int k = 1; k < searcher_k; ++k) dist_sum += std::sqrt(double(nn_dists[std::size_t(k)]));  // :92-93
    o.distances[i] = static_cast<float>(dist_sum / mean_k);                                        // :94
    valid_distances++;
  }
  double sum = 0, sq_sum = 0;
  for (const float& distance : o.distances) {
    sum += distance;
    sq_sum += distance * distance;  // :103, a float product
  }
  o.mean = sum / static_cast<double>(valid_distances);
  const double variance = (sq_sum - sum * sum / static_cast<double>(valid_distances)) /
                          (static_cast<double>(valid_distances) - 1);  // :106
  o.stddev = std::sqrt(variance);
  return o;
}

/// RadiusOutlierRemoval<PointT>::applyFilterIndices on a dense cloud (radius_outlier_removal.hpp:49-130).
std::vector<std::uint32_t> rorOracle(const std::vector<point3d>& pts, double search_radius, int min_pts_radius) {
  if (search_radius == 0.0) return {};  // :51-57
  const int mean_k = min_pts_radius + 1;
  const double nn_dists_max = search_radius * search_radius;
  std::vector<std::uint32_t> out;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const auto nn_dists = pclNnDists(pts, i, std::size_t(mean_k), false);
    const int k = int(nn_dists.size());
    const bool chk_neighbors = k == mean_k && !(nn_dists_max < nn_dists[std::size_t(k - 1)]);  // :88-116
    if (chk_neighbors) out.push_back(std::uint32_t(i));
  }
  return out;
}

bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0 || (std::isnan(a) && std::isnan(b)); }

std::vector<std::uint32_t> all(std::size_t n) {
  std::vector<std::uint32_t> v(n);
  for (std::size_t i = 0; i < n; ++i) v[i] = std::uint32_t(i);
  return v;
}

}  // namespace

TEST_CASE("SOR distances, mean, stddev and kept indices equal the brute-force PCL oracle bit for bit") {
  for (std::uint64_t seed = 1; seed <= test::kFilterSeeds; ++seed) {
    const auto c = test::filterCase(seed);
    INFO("seed " << seed << " (" << c.kind << ", " << c.points.size() << " points, mean_k " << c.mean_k << ")");
    const SorDistances d = sorDistances(c.points, c.mean_k);
    const SorOracle o = sorOracle(c.points, c.mean_k);
    REQUIRE(d.mean_distance == o.distances);
    REQUIRE(sameBits(d.threshold_mean, o.mean));
    REQUIRE(sameBits(d.threshold_stddev, o.stddev));
    for (double std_mul : test::kStdMuls) {
      INFO("std_mul " << std_mul);
      REQUIRE(statisticalOutlierRemoval(c.points, c.mean_k, std_mul) == o.kept(std_mul));
    }
    // The filter off: nothing removed (NaN thresholds of 0 or 1 point keep everything too).
    CHECK(statisticalOutlierRemoval(c.points, c.mean_k, 1e9) == all(c.points.size()));
  }
}

TEST_CASE("ROR neighbour counts and kept indices equal the brute-force PCL oracle, points at the radius included") {
  for (std::uint64_t seed = 1; seed <= test::kFilterSeeds; ++seed) {
    const auto c = test::filterCase(seed);
    INFO("seed " << seed << " (" << c.kind << ", " << c.points.size() << " points)");
    for (double radius : c.radii) {
      const auto counts = rorNeighbourCounts(c.points, radius);
      for (int min_neighbors : test::kMinNeighbours) {
        INFO("radius " << radius << " min_neighbors " << min_neighbors);
        const auto expected = rorOracle(c.points, radius, min_neighbors);
        REQUIRE(radiusOutlierRemoval(c.points, radius, min_neighbors) == expected);
        std::vector<std::uint32_t> by_count;
        for (std::size_t i = 0; i < counts.size(); ++i)
          if (rorKeeps(counts[i], min_neighbors)) by_count.push_back(std::uint32_t(i));
        REQUIRE(by_count == expected);
      }
    }
    CHECK(radiusOutlierRemoval(c.points, 0.3, 0) == all(c.points.size()));
  }
}

TEST_CASE("SOR by hand: three points on a line, mean_k 1 and 2, sample standard deviation") {
  const std::vector<point3d> pts = {{0, 0, 0}, {1, 0, 0}, {3, 0, 0}};
  const auto k1 = sorDistances(pts, 1);
  CHECK(k1.mean_distance == std::vector<float>{1.0f, 1.0f, 2.0f});
  CHECK(k1.threshold_mean == Approx(4.0 / 3));
  CHECK(k1.threshold_stddev == Approx(std::sqrt(1.0 / 3)));  // sample (n-1): population would be sqrt(2)/3
  // mean + 1 * stddev = 1.911 < 2: the far point goes; std_mul 2 keeps it (threshold 2.488).
  CHECK(statisticalOutlierRemoval(pts, 1, 1.0) == std::vector<std::uint32_t>{0, 1});
  CHECK(statisticalOutlierRemoval(pts, 1, 2.0) == all(3));
  // Fewer than mean_k + 1 points: the sum of the two others is still divided by mean_k (5 here).
  CHECK(sorDistances(pts, 5).mean_distance == std::vector<float>{4.0f / 5, 3.0f / 5, 5.0f / 5});
}

TEST_CASE("SOR edge cases: empty cloud, one point (NaN stddev keeps it), equal distances, strict comparison") {
  const auto empty = sorDistances({}, 3);
  CHECK(empty.mean_distance.empty());
  CHECK(std::isnan(empty.threshold_mean));
  CHECK(statisticalOutlierRemoval({}, 3, 1.0).empty());
  const auto one = sorDistances({{1, 2, 3}}, 3);
  CHECK(one.mean_distance == std::vector<float>{0.0f});
  CHECK(std::isnan(one.threshold_stddev));  // (0 - 0/1) / (1 - 1)
  CHECK(statisticalOutlierRemoval({{1, 2, 3}}, 3, -1.0) == all(1));
  CHECK(sorKeeps(1.0f, 1.0));  // equal to the threshold: kept (PCL removes only distances > threshold)
  CHECK_FALSE(sorKeeps(std::nextafter(1.0f, 2.0f), 1.0));
  CHECK(sorKeeps(5.0f, std::numeric_limits<double>::quiet_NaN()));
  CHECK_THROWS_AS(sorDistances({{0, 0, 0}}, 0), std::invalid_argument);
  CHECK_THROWS_AS(sorDistances({{0, 0, std::numeric_limits<float>::quiet_NaN()}}, 1), std::invalid_argument);
}

TEST_CASE("ROR by hand: a neighbour exactly at the radius counts, the point itself does not, radius 0 keeps none") {
  const std::vector<point3d> pts = {{0, 0, 0}, {1, 0, 0}, {1, 0, 0}, {5, 0, 0}};
  CHECK(rorNeighbourCounts(pts, 1.0) == std::vector<std::uint32_t>{2, 2, 2, 0});
  CHECK(rorNeighbourCounts(pts, std::nextafter(1.0, 0.0)) == std::vector<std::uint32_t>{0, 1, 1, 0});
  CHECK(radiusOutlierRemoval(pts, 1.0, 2) == std::vector<std::uint32_t>{0, 1, 2});
  CHECK(radiusOutlierRemoval(pts, 1.0, 3).empty());
  CHECK(radiusOutlierRemoval(pts, 1.0, 0) == all(4));
  CHECK(radiusOutlierRemoval(pts, -1.0, 2) == std::vector<std::uint32_t>{0, 1, 2});  // only radius^2 is used
  CHECK(radiusOutlierRemoval(pts, 0.0, 0).empty());
  CHECK(radiusOutlierRemoval({}, 1.0, 1).empty());
  CHECK_THROWS_AS(rorKeeps(3, -1), std::invalid_argument);
  CHECK_THROWS_AS(rorNeighbourCounts(pts, std::numeric_limits<double>::quiet_NaN()), std::invalid_argument);
}

namespace {

/// rorNeighbourCounts by brute force: the other points at !(r^2 < double(FLANN d2)) (radius_outlier_removal.hpp:104).
std::vector<std::uint32_t> rorCountsOracle(const std::vector<point3d>& pts, double radius) {
  std::vector<std::uint32_t> counts(pts.size(), 0);
  for (std::size_t i = 0; i < pts.size(); ++i)
    for (std::size_t j = 0; j < pts.size(); ++j)
      counts[i] += j != i && !(radius * radius < double(flannL2(pts[i], pts[j])));
  return counts;
}

/// The radius of the cloud's farthest pair by FLANN's d2: that pair lies exactly at it or a rounding beside it.
double diameter(const std::vector<point3d>& pts) {
  float d2 = 0;
  for (const auto& a : pts)
    for (const auto& b : pts) d2 = std::max(d2, flannL2(a, b));
  return std::sqrt(double(d2));
}

/// limits().neighbour_distances set for one scope.
struct NeighbourLimit {
  explicit NeighbourLimit(std::uint64_t limit) : saved(limits().neighbour_distances) {
    limits().neighbour_distances = limit;
  }
  ~NeighbourLimit() { limits().neighbour_distances = saved; }
  std::uint64_t saved;
};

}  // namespace

TEST_CASE("ROR counts equal brute force for radii from below the spacing to past the whole cloud") {
  // The counting tree settles whole boxes inside or outside the sphere; the cloud's farthest pair sits on the
  // boundary at its diameter, and every point is everyone's neighbour past it.
  for (std::uint64_t seed = 1; seed <= test::kFilterSeeds; ++seed) {
    const auto c = test::filterCase(seed);
    std::vector<double> radii = c.radii;
    const double d = diameter(c.points);
    radii.insert(radii.end(), {d, std::nextafter(d, 0.0), d / 2, 2 * d, 1e6, 0.0});
    for (double radius : radii) {
      INFO("seed " << seed << " (" << c.kind << ", " << c.points.size() << " points), radius " << radius);
      REQUIRE(rorNeighbourCounts(c.points, radius) == rorCountsOracle(c.points, radius));
    }
  }
}

TEST_CASE("ROR's count tree measures no distance for a radius past the cloud, and few for half of it") {
  // The finding: radius 100 on a 200,000-point scan measured every pair (n^2). Here boxes settle every pair.
  SplitMix64 rng(11);
  std::vector<point3d> pts;
  for (int i = 0; i < 20000; ++i)
    pts.emplace_back(float(rng.uniform() * 4), float(rng.uniform() * 4), float(rng.uniform()));
  for (double radius : {6.0, 100.0, 1e6}) {
    detail::RadiusCountTree tree(pts);
    for (const auto& p : pts) REQUIRE(tree.countWithin(p, radius * radius) == pts.size());
    CHECK(tree.distancesMeasured() == 0);
  }
  detail::RadiusCountTree tree(pts);
  const std::size_t n = pts.size();
  for (std::size_t i = 0; i < n; i += 100) (void)tree.countWithin(pts[i], 2.0 * 2.0);
  INFO("distances measured for 200 queries at radius 2: " << tree.distancesMeasured());
  CHECK(tree.distancesMeasured() < 200 * n / 10);  // brute force measures 200 n
}

TEST_CASE("SOR with k past the sorted array and past the cloud's size (PCL caps it) equals the oracle bit for bit") {
  for (std::uint64_t seed = 1; seed <= 30; ++seed) {
    const auto c = test::filterCase(seed);
    const int n = int(c.points.size());
    for (int mean_k : {129, n / 2 + 1, n - 1, n, n + 1, 100000}) {
      if (mean_k < 1) continue;
      INFO("seed " << seed << " (" << c.kind << ", " << n << " points, mean_k " << mean_k << ")");
      const SorDistances d = sorDistances(c.points, mean_k);
      const SorOracle o = sorOracle(c.points, mean_k);
      REQUIRE(d.mean_distance == o.distances);
      REQUIRE(sameBits(d.threshold_mean, o.mean));
      REQUIRE(sameBits(d.threshold_stddev, o.stddev));
    }
  }
}

TEST_CASE("SOR refuses more neighbour distances than the limit before searching, n x min(k, n - 1) of them") {
  SplitMix64 rng(3);
  std::vector<point3d> pts;
  for (int i = 0; i < 1000; ++i) pts.emplace_back(float(rng.uniform()), float(rng.uniform()), float(rng.uniform()));
  {
    const NeighbourLimit exactly(1000 * 999);  // k capped at the 999 others
    CHECK(sorDistances(pts, 100000).mean_distance.size() == 1000);
  }
  const NeighbourLimit below(1000 * 999 - 1);
  CHECK(sorDistances(pts, 998).mean_distance.size() == 1000);
  try {
    (void)statisticalOutlierRemoval(pts, 100000, 1.0);
    FAIL("no LimitError");
  } catch (const LimitError& e) {
    const std::string message = e.what();
    INFO(message);
    for (const char* word : {"sor-octomap: k 100000", "1000 points", "999000 is more than the limit of 998999",
                             "--max-neighbour-distances"})
      CHECK(message.find(word) != std::string::npos);
  }
}
