// Oracles for the k-NN model's statistics: k-d tree against brute force, Welford against two passes,
// the normal CDF and Eq. 6 against hand-computed values.
#include <catch2/catch.hpp>

#include <cmath>

#include "occsweep/methods/knn/knn_average_distance.hpp"
#include "occsweep/methods/knn/normal_cdf.hpp"
#include "occsweep/core/welford.hpp"
#include "test_helpers.hpp"

using namespace occsweep;

TEST_CASE("the nanoflann k-d tree's average k-NN distances equal brute force on random clouds") {
  for (std::uint64_t seed = 1; seed <= 40; ++seed) {
    SplitMix64 rng(seed);
    const std::size_t n = 1 + rng.below(300);
    auto pts = test::randomCloud(rng, n, 2.0);
    // Duplicates: a point at distance 0 is still another point.
    for (std::size_t d = 0; d < n / 10; ++d) pts.push_back(pts[rng.below(pts.size())]);
    const int k = 1 + int(rng.below(9));
    const auto fast = averageKnnDistancesKdTree(pts, k);
    const auto slow = averageKnnDistancesBruteForce(pts, k);
    REQUIRE(fast.size() == slow.size());
    for (std::size_t i = 0; i < fast.size(); ++i) {
      INFO("seed " << seed << " point " << i << " k " << k);
      REQUIRE(fast[i] == Approx(slow[i]).epsilon(1e-12));
    }
  }
}

TEST_CASE("average k-NN distance with fewer than k others, and none") {
  std::vector<octomap::point3d> pts = {{0, 0, 0}, {3, 0, 0}, {0, 4, 0}};
  const auto s = averageKnnDistances(pts, 5);  // only two others each
  CHECK(s[0] == Approx((3.0 + 4.0) / 2));
  CHECK(s[1] == Approx((3.0 + 5.0) / 2));
  CHECK(s[2] == Approx((4.0 + 5.0) / 2));
  const auto k1 = averageKnnDistances(pts, 1);
  CHECK(k1[0] == Approx(3.0));
  CHECK(k1[2] == Approx(4.0));
  const auto alone = averageKnnDistances({{1, 2, 3}}, 3);
  CHECK(std::isinf(alone[0]));
}

TEST_CASE("Welford (Eq. 9-10) equals the two-pass mean and population deviation") {
  for (std::uint64_t seed = 1; seed <= 30; ++seed) {
    SplitMix64 rng(seed);
    std::vector<double> v(1 + rng.below(1000));
    for (auto& x : v) x = 1e3 + rng.gaussian() * 0.01;  // large offset: where naive sums lose digits
    Welford w;
    for (double x : v) w.add(x);
    double mean = 0;
    for (double x : v) mean += x;
    mean /= double(v.size());
    double q = 0;
    for (double x : v) q += (x - mean) * (x - mean);
    CHECK(w.count() == v.size());
    CHECK(w.mean() == Approx(mean).epsilon(1e-14));
    CHECK(w.sigma() == Approx(std::sqrt(q / double(v.size()))).epsilon(1e-9).margin(1e-15));
  }
  Welford w;  // hand case: 2, 4, 4, 4, 5, 5, 7, 9 -> mean 5, population sigma 2
  for (double x : {2, 4, 4, 4, 5, 5, 7, 9}) w.add(x);
  CHECK(w.mean() == 5.0);
  CHECK(w.sigma() == Approx(2.0).epsilon(1e-15));
}

TEST_CASE("normal CDF and Eq. 6 against hand-computed values") {
  // Reference values of Phi to 16 digits; a relative 1e-14 leaves room only for double rounding.
  const auto near = [](double v) { return Approx(v).epsilon(1e-14); };
  CHECK(normalCdf(1.0, 1.0, 0.5) == near(0.5));
  CHECK(normalCdf(1.5, 1.0, 0.5) == near(0.8413447460685429));  // Phi(1)
  CHECK(normalCdf(0.0, 1.0, 0.5) == near(0.0227501319481792));  // Phi(-2)
  CHECK(normalCdf(0.2, 0.1, 0.0) == 1.0);                       // sigma 0: a step at mu
  CHECK(normalCdf(0.05, 0.1, 0.0) == 0.0);
  CHECK(normalCdf(INFINITY, 0.1, 0.02) == 1.0);
  // Eq. 6: p(s) = p_u - F(s)(p_u - p_l)
  CHECK(pointProbability(1.0, 1.0, 0.5, 0.9, 0.3) == near(0.6));
  CHECK(pointProbability(1.5, 1.0, 0.5, 0.9, 0.3) == near(0.9 - 0.8413447460685429 * 0.6));
  CHECK(pointProbability(INFINITY, 1.0, 0.5, 0.9, 0.3) == near(0.3));
  CHECK(pointProbability(-1e9, 1.0, 0.5, 0.9, 0.3) == near(0.9));
}
