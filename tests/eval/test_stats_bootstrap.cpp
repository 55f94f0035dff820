// Bootstrap confidence intervals of a mean (docs/statistics.md): coverage over seeded synthetic populations,
// the degenerate all-zero case, seeding, and the normal quantile they rest on.
#include <cmath>
#include <stdexcept>
#include <vector>

#include <catch2/catch.hpp>

#include "occsweep/core/splitmix64.hpp"
#include "occsweep/stats/bootstrap.hpp"

using namespace occsweep::stats;
using occsweep::SplitMix64;

namespace {

/// Share of `trials` samples of n = 30 from N(mu, sigma) whose interval contains mu.
double coverage(BootstrapMethod method, double level, int trials) {
  const double mu = 0.002, sigma = 0.004;  // AUC differences of the size compare reports
  SplitMix64 population(2022);
  int covered = 0;
  for (int trial = 0; trial < trials; ++trial) {
    std::vector<double> sample(30);
    for (double& v : sample) v = mu + sigma * population.gaussian();
    const auto interval = bootstrapMeanInterval(sample, {level, 1000, std::uint64_t(trial) + 1, method});
    covered += interval.contains(mu) ? 1 : 0;
  }
  return double(covered) / double(trials);
}

/// Requires an observed coverage of 1,000 trials within 3 binomial standard errors (a false alarm has
/// probability 0.003) of the coverage a correct bootstrap interval of the mean has for n = 30 normal values.
/// That is not quite the nominal level: such an interval is close to a z-interval with the plug-in standard
/// deviation, whose coverage is 2 F_t29(z sqrt(29/30)) - 1 = 0.9362 at level 0.95 and 0.7823 at level 0.80
/// (the "narrowness bias" of bootstrap intervals for small n, Hesterberg 2015, The American Statistician 69(4)).
void requireNearExpected(double observed, double level, double expected) {
  const double standard_error = std::sqrt(expected * (1.0 - expected) / 1000.0);
  INFO("coverage " << observed << " at level " << level << ", expected " << expected);
  CHECK(std::fabs(observed - expected) <= 3.0 * standard_error);
}

}  // namespace

TEST_CASE("Percentile and BCa intervals cover the true mean at close to their level", "[stats]") {
  for (auto method : {BootstrapMethod::Percentile, BootstrapMethod::BCa}) {
    // Reproduce the expected values: /usr/bin/python3 -c "from scipy import stats; import math;
    // print([2 * stats.t.cdf(stats.norm.ppf(1 - (1 - L) / 2) * math.sqrt(29 / 30), 29) - 1 for L in (0.95, 0.8)])"
    requireNearExpected(coverage(method, 0.95, 1000), 0.95, 0.9362);
    requireNearExpected(coverage(method, 0.80, 1000), 0.80, 0.7823);
  }
}

TEST_CASE("Identical methods (every difference zero) give the interval [0, 0], which contains 0", "[stats]") {
  const std::vector<double> zeros(60, 0.0);
  for (auto method : {BootstrapMethod::Percentile, BootstrapMethod::BCa}) {
    const auto interval = bootstrapMeanInterval(zeros, {0.95, 2000, 5, method});
    CHECK(interval.lower == 0.0);
    CHECK(interval.upper == 0.0);
    CHECK(interval.contains(0.0));
  }
}

TEST_CASE("The same seed gives the same interval, another seed another one", "[stats]") {
  SplitMix64 rng(9);
  std::vector<double> sample(40);
  for (double& v : sample) v = rng.gaussian();
  const BootstrapOptions options{0.95, 2000, 42, BootstrapMethod::BCa};
  const auto first = bootstrapMeanInterval(sample, options);
  const auto again = bootstrapMeanInterval(sample, options);
  CHECK(first.lower == again.lower);
  CHECK(first.upper == again.upper);
  auto other_seed = options;
  other_seed.seed = 43;
  const auto other = bootstrapMeanInterval(sample, other_seed);
  CHECK((other.lower != first.lower || other.upper != first.upper));
  CHECK(first.lower < first.estimate);
  CHECK(first.estimate < first.upper);
}

TEST_CASE("BCa moves the interval towards the long tail of a skewed sample", "[stats]") {
  // Exponential data: the mean's sampling distribution is right-skewed, so BCa's upper end lies further from
  // the estimate than the percentile interval's (Efron & Tibshirani 1993, ch. 14).
  SplitMix64 rng(14);
  std::vector<double> sample(25);
  for (double& v : sample) v = -std::log(1.0 - rng.uniform());
  const auto percentile = bootstrapMeanInterval(sample, {0.95, 4000, 1, BootstrapMethod::Percentile});
  const auto bca = bootstrapMeanInterval(sample, {0.95, 4000, 1, BootstrapMethod::BCa});
  CHECK(bca.upper > percentile.upper);
  CHECK(bca.lower > percentile.lower);
}

TEST_CASE("The normal quantile and the type-7 sample quantile", "[stats]") {
  CHECK(normalQuantile(0.975) == Approx(1.959963984540054).epsilon(1e-14));
  CHECK(normalQuantile(1e-10) == Approx(-6.361340902404056).epsilon(1e-13));
  CHECK(std::fabs(normalQuantile(0.5)) < 1e-15);
  for (double p : {1e-6, 0.01, 0.3, 0.9, 0.999999}) CHECK(normalCdf(normalQuantile(p)) == Approx(p).epsilon(1e-13));
  const std::vector<double> sorted{1.0, 2.0, 3.0, 4.0};
  CHECK(sortedQuantile(sorted, 0.0) == 1.0);
  CHECK(sortedQuantile(sorted, 0.5) == 2.5);
  CHECK(sortedQuantile(sorted, 1.0) == 4.0);
  CHECK(sortedQuantile(sorted, 1.0 / 3.0) == Approx(2.0).epsilon(1e-15));
}

TEST_CASE("The bootstrap refuses an empty sample, non-finite values, a level outside (0, 1), no resamples",
          "[stats]") {
  CHECK_THROWS_AS(bootstrapMeanInterval({}), std::invalid_argument);
  CHECK_THROWS_WITH(bootstrapMeanInterval({1.0, INFINITY}), Catch::Contains("value 1 is not finite"));
  CHECK_THROWS_WITH(bootstrapMeanInterval({1.0, 2.0}, {1.0, 100, 1, BootstrapMethod::BCa}),
                    Catch::Contains("level"));
  CHECK_THROWS_WITH(bootstrapMeanInterval({1.0, 2.0}, {0.9, 0, 1, BootstrapMethod::BCa}),
                    Catch::Contains("resamples"));
}
