// Budget curves (docs/statistics.md): the exact order-statistic formula against brute-force enumeration of every
// subset on small grids and against seeded sampling on a grid the size of the paper's k-NN grid.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <vector>

#include <catch2/catch.hpp>

#include "occsweep/core/splitmix64.hpp"
#include "occsweep/stats/budget_curve.hpp"

using occsweep::SplitMix64;
using occsweep::stats::expectedBestCurve;
using occsweep::stats::firstBudgetAbove;

namespace {

/// AUC-like values with ties: rounded to `step`.
std::vector<double> randomGrid(SplitMix64& rng, std::size_t n, double step) {
  std::vector<double> grid(n);
  for (double& auc : grid) auc = std::round((0.8 + 0.2 * rng.uniform()) / step) * step;
  return grid;
}

/// Mean over every subset of each size of its maximum, by enumerating the 2^N subsets.
std::vector<double> bruteForceCurve(const std::vector<double>& grid) {
  const std::size_t n = grid.size();
  std::vector<double> sum_of_max(n + 1, 0.0), subsets(n + 1, 0.0);
  for (std::uint32_t mask = 1; mask < (1u << n); ++mask) {
    double best = -std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < n; ++i)
      if (mask & (1u << i)) best = std::max(best, grid[i]);
    const auto size = std::size_t(__builtin_popcount(mask));
    sum_of_max[size] += best;
    subsets[size] += 1.0;
  }
  std::vector<double> curve(n);
  for (std::size_t size = 1; size <= n; ++size) curve[size - 1] = sum_of_max[size] / subsets[size];
  return curve;
}

struct SampledBest {
  double mean = 0.0;
  double standard_error = 0.0;
};

/// The best of `budget` distinct combinations, drawn by a partial Fisher-Yates shuffle, over `draws` draws.
SampledBest sampledBest(std::vector<double> grid, std::size_t budget, std::size_t draws, SplitMix64& rng) {
  double sum = 0.0, sum_of_squares = 0.0;
  for (std::size_t d = 0; d < draws; ++d) {
    double best = -std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < budget; ++i) {
      std::swap(grid[i], grid[i + rng.below(grid.size() - i)]);
      best = std::max(best, grid[i]);
    }
    sum += best;
    sum_of_squares += best * best;
  }
  const double mean = sum / double(draws);
  const double variance = std::max(0.0, sum_of_squares / double(draws) - mean * mean) * double(draws) /
                          double(draws - 1);
  return {mean, std::sqrt(variance / double(draws))};
}

}  // namespace

TEST_CASE("The budget curve equals the mean best over every subset of each size, ties included", "[stats]") {
  SplitMix64 rng(17);
  for (std::size_t size = 1; size <= 12; ++size)
    for (int repeat = 0; repeat < 4; ++repeat) {
      const auto grid = randomGrid(rng, size, repeat % 2 == 0 ? 0.01 : 0.1);  // 0.1 steps: many ties
      const auto exact = expectedBestCurve(grid);
      const auto brute = bruteForceCurve(grid);
      REQUIRE(exact.size() == size);
      for (std::size_t n = 0; n < size; ++n) {
        INFO("grid size " << size << ", budget " << n + 1);
        CHECK(exact[n] == Approx(brute[n]).epsilon(1e-13));
      }
    }
}

TEST_CASE("On a 4,050-combination grid the budget curve agrees with seeded sampling within 4 standard errors",
          "[stats]") {
  SplitMix64 rng(4050);
  std::vector<double> grid(4050);
  for (double& auc : grid) auc = 0.95 - 0.1 * std::pow(rng.uniform(), 0.3);  // skewed: few near the top
  const auto exact = expectedBestCurve(grid);
  // 2,000 draws per budget: the test fails when |exact - sample mean| > 4 SE (a false alarm has probability
  // 6e-5 per budget).
  for (std::size_t budget : {1u, 2u, 10u, 180u, 1000u, 4049u}) {
    const auto sample = sampledBest(grid, budget, 2000, rng);
    INFO("budget " << budget << ": exact " << exact[budget - 1] << ", sampled " << sample.mean << " +- "
                   << sample.standard_error);
    CHECK(std::fabs(exact[budget - 1] - sample.mean) <= 4.0 * sample.standard_error + 1e-15);
  }
  CHECK(exact.back() == *std::max_element(grid.begin(), grid.end()));
  CHECK(exact.front() == Approx(std::accumulate(grid.begin(), grid.end(), 0.0) / 4050.0).epsilon(1e-12));
  for (std::size_t n = 1; n < exact.size(); ++n) REQUIRE(exact[n] >= exact[n - 1] - 1e-15);
}

TEST_CASE("Identical grids give identical curves: a budget gap of zero, never above their own best", "[stats]") {
  SplitMix64 rng(3);
  const auto grid = randomGrid(rng, 180, 0.001);
  auto shuffled = grid;
  std::reverse(shuffled.begin(), shuffled.end());
  const auto a = expectedBestCurve(grid);
  const auto b = expectedBestCurve(shuffled);
  REQUIRE(a == b);
  CHECK_FALSE(firstBudgetAbove(a, b.back()).has_value());
  const std::vector<double> constant(50, 0.93);
  for (double best : expectedBestCurve(constant)) CHECK(best == 0.93);
}

TEST_CASE("The first budget above a value: strictly above, 1-based, none when never passed", "[stats]") {
  const auto curve = expectedBestCurve({0.0, 1.0});  // best of 1: 0.5, best of 2: 1
  REQUIRE(curve == std::vector<double>{0.5, 1.0});
  CHECK(firstBudgetAbove(curve, 0.4) == 1u);
  CHECK(firstBudgetAbove(curve, 0.5) == 2u);
  CHECK_FALSE(firstBudgetAbove(curve, 1.0).has_value());
}

TEST_CASE("A budget curve refuses an empty grid and non-finite AUCs", "[stats]") {
  CHECK_THROWS_AS(expectedBestCurve({}), std::invalid_argument);
  CHECK_THROWS_WITH(expectedBestCurve({0.5, std::nan("")}), Catch::Contains("value 1 is not finite"));
}
