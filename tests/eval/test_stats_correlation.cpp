// Pearson r, Spearman rho, the permutation test of a correlation and correlations within groups
// (docs/statistics.md, "Correlation"). Reference values come from SciPy 1.10.1 through
// tools/correlation_reference.py, committed as tests/correlation_reference_cases.hpp so that this test runs without
// SciPy; the last test case re-runs the script where SciPy is installed and requires the same output.
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <string>

#include <catch2/catch.hpp>

#include "correlation_reference_cases.hpp"
#include "occsweep/stats/correlation.hpp"
#include "reference_script_check.hpp"
#include "test_helpers.hpp"

using namespace occsweep::stats;
using occsweep::test::kCorrelationReferenceCases;

namespace {

constexpr double kMargin = 1e-12;
constexpr std::size_t kResamples = 10000;

const occsweep::test::CorrelationReferenceCase& caseNamed(const std::string& name) {
  for (const auto& reference : kCorrelationReferenceCases)
    if (reference.name == name) return reference;
  throw std::invalid_argument("no reference case " + name);
}

double factorial(std::size_t n) { return n <= 1 ? 1.0 : double(n) * factorial(n - 1); }

/// Four binomial standard errors of the difference between our Monte Carlo p (kResamples) and SciPy's
/// (`reference_resamples`), plus the +1 of the p-value's numerator: a wrong test misses it, a right one passes
/// with probability above 0.9999 per comparison.
double monteCarloTolerance(double p, std::size_t reference_resamples) {
  const double variance = p * (1.0 - p) * (1.0 / double(kResamples) + 1.0 / double(reference_resamples));
  return 4.0 * std::sqrt(variance) + 1.0 / double(kResamples + 1);
}

void checkPermutationTest(const occsweep::test::CorrelationReferenceCase& reference, CorrelationKind kind,
                          double reference_p) {
  const auto result = correlationPermutationTest(reference.x, reference.y, {kind, kResamples, 1});
  CHECK(result.statistic == correlation(reference.x, reference.y, kind));
  if (reference.resamples == 0) {
    CHECK(result.exact);
    CHECK(double(result.permutations) == factorial(reference.x.size()));
    CHECK(result.p_value == Approx(reference_p).margin(kMargin));
  } else {
    CHECK_FALSE(result.exact);
    CHECK(result.permutations == kResamples);
    CHECK(result.p_value == Approx(reference_p).margin(monteCarloTolerance(reference_p, reference.resamples)));
  }
}

}  // namespace

TEST_CASE("Pearson r and Spearman rho equal SciPy's pearsonr and spearmanr, ties included", "[stats]") {
  REQUIRE(kCorrelationReferenceCases.size() >= 10);
  for (const auto& reference : kCorrelationReferenceCases) {
    INFO("case " << reference.name);
    CHECK(pearsonCorrelation(reference.x, reference.y) == Approx(reference.pearson).margin(kMargin));
    CHECK(spearmanCorrelation(reference.x, reference.y) == Approx(reference.spearman).margin(kMargin));
  }
}

TEST_CASE("Permutation p-values equal SciPy's permutation_test: exactly up to 8 pairs, within 4 SE above",
          "[stats]") {
  int exact = 0;
  for (const auto& reference : kCorrelationReferenceCases) {
    INFO("case " << reference.name);
    checkPermutationTest(reference, CorrelationKind::Pearson, reference.pearson_permutation_p);
    checkPermutationTest(reference, CorrelationKind::Spearman, reference.spearman_permutation_p);
    exact += reference.resamples == 0 ? 1 : 0;
  }
  CHECK(exact >= 4);
}

TEST_CASE("The Monte Carlo p-value is (count + 1) / (resamples + 1), seeded and repeatable", "[stats]") {
  std::vector<double> x, y;
  for (int i = 0; i < 20; ++i) x.push_back(i), y.push_back(3.0 * i - 1.0);
  // No other permutation of 20 values reaches |r| = 1 in 999 draws (chance about 2 / 20!): p = 1 / 1000.
  CHECK(correlationPermutationTest(x, y, {CorrelationKind::Pearson, 999, 7}).p_value == 1.0 / 1000.0);
  const auto& weak = caseNamed("ties_n30");  // p near 0.65: another seed gives another count
  const auto once = correlationPermutationTest(weak.x, weak.y, {CorrelationKind::Pearson, 2000, 3});
  const auto again = correlationPermutationTest(weak.x, weak.y, {CorrelationKind::Pearson, 2000, 3});
  const auto other = correlationPermutationTest(weak.x, weak.y, {CorrelationKind::Pearson, 2000, 4});
  CHECK(once.p_value == again.p_value);
  CHECK(once.p_value != other.p_value);
}

TEST_CASE("Simpson's paradox: positive within each group, negative over both", "[stats]") {
  // Group a lies high and left, group b low and right; inside each, y rises with x (r = rho = 0.8 by hand:
  // centred x -1.5, -0.5, 0.5, 1.5 against y -1.5, 0.5, -0.5, 1.5 give 4 / 5).
  const std::vector<double> x{1, 2, 3, 4, 11, 12, 13, 14};
  const std::vector<double> y{11, 13, 12, 14, 1, 3, 2, 4};
  const std::vector<std::string> group{"b", "b", "b", "b", "a", "a", "a", "a"};
  CHECK(pearsonCorrelation(x, y) == Approx(-32.0 / 35.0).margin(kMargin));  // SciPy: -0.9142857142857144
  CHECK(spearmanCorrelation(x, y) == Approx(-4.0 / 7.0).margin(kMargin));   // SciPy: -0.5714285714285715
  const auto within = correlationWithinGroups(x, y, group);
  REQUIRE(within.size() == 2);
  CHECK(within[0].group == "a");  // sorted by label
  for (const auto& g : within) {
    INFO("group " << g.group);
    CHECK(g.n == 4);
    CHECK(g.pearson == Approx(0.8).margin(kMargin));
    CHECK(g.spearman == Approx(0.8).margin(kMargin));
  }
  CHECK(pooledWithinGroupPearson(x, y, group) == Approx(0.8).margin(kMargin));
  CHECK(correlationPermutationTest(x, y).exact);
}

TEST_CASE("Correlations within groups equal the correlations of each group's pairs", "[stats]") {
  const auto& reference = caseNamed("strong_n60");
  std::vector<std::string> group;
  std::vector<double> xa, ya;
  for (std::size_t i = 0; i < reference.x.size(); ++i) {
    group.push_back(i % 3 == 0 ? "three" : "rest");
    if (i % 3 == 0) xa.push_back(reference.x[i]), ya.push_back(reference.y[i]);
  }
  group[1] = "single";
  const auto within = correlationWithinGroups(reference.x, reference.y, group);
  REQUIRE(within.size() == 3);
  CHECK(within[0].group == "rest");
  CHECK(within[1].group == "single");
  CHECK(within[1].n == 1);
  CHECK(std::isnan(within[1].pearson));
  CHECK(within[2].n == xa.size());
  CHECK(within[2].pearson == pearsonCorrelation(xa, ya));
  CHECK(within[2].spearman == spearmanCorrelation(xa, ya));
  // One group: the pooled within-group r is the plain r.
  const std::vector<std::string> one(reference.x.size(), "all");
  CHECK(pooledWithinGroupPearson(reference.x, reference.y, one) ==
        Approx(pearsonCorrelation(reference.x, reference.y)).margin(kMargin));
}

TEST_CASE("Correlation refuses bad input, naming the function and the index", "[stats]") {
  CHECK_THROWS_WITH(pearsonCorrelation({1, 2}, {1, 2, 3}), Catch::Contains("pearsonCorrelation: x has 2 values"));
  CHECK_THROWS_WITH(spearmanCorrelation({1, NAN, 3}, {1, 2, 3}), Catch::Contains("value 1 is not finite"));
  CHECK_THROWS_WITH(pearsonCorrelation({1}, {1}), Catch::Contains("at least 2 pairs"));
  CHECK(std::isnan(pearsonCorrelation({1, 1, 1}, {1, 2, 3})));  // constant x: undefined, as in SciPy
  CHECK(std::isnan(spearmanCorrelation({1, 2, 3}, {4, 4, 4})));
  CHECK_THROWS_WITH(correlationPermutationTest({1, 1, 1}, {1, 2, 3}), Catch::Contains("constant"));
  CHECK_THROWS_WITH(correlationPermutationTest({1, 2, 3}, {1, 2, 3}, {CorrelationKind::Pearson, 0, 1}),
                    Catch::Contains("resamples"));
  CHECK_THROWS_WITH(correlationWithinGroups({1, 2}, {1, 2}, {"a"}),
                    Catch::Contains("correlationWithinGroups: 1 group labels for 2 pairs"));
  CHECK_THROWS_WITH(pooledWithinGroupPearson({1, 2}, {1, INFINITY}, {"a", "a"}),
                    Catch::Contains("pooledWithinGroupPearson (y): value 1 is not finite"));
}

TEST_CASE("tools/correlation_reference.py still prints the committed reference values", "[stats]") {
  occsweep::test::requireReferenceScriptUnchanged("correlation_reference",
                                                 "import scipy; assert scipy.__version__ == \"1.10.1\"",
                                                 "SciPy 1.10.1");
}
