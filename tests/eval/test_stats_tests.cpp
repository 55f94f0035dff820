// Wilcoxon signed-rank test, sign test and effect sizes (docs/statistics.md). Reference p-values come from SciPy
// 1.10.1 through tools/stats_reference.py, committed as tests/stats_reference_cases.hpp so that this test runs
// without SciPy; the last test case re-runs the script where SciPy is installed and requires the same output.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include <catch2/catch.hpp>

#include "occsweep/stats/effect_size.hpp"
#include "occsweep/stats/sign_test.hpp"
#include "occsweep/stats/wilcoxon.hpp"
#include "stats_reference_cases.hpp"
#include "reference_script_check.hpp"
#include "test_helpers.hpp"

using namespace occsweep::stats;
using occsweep::test::kStatsReferenceCases;

namespace {

constexpr double kRelative = 1e-9;  // erfc and lgamma against SciPy's: the largest difference measured is 6e-14

bool tiedOrZero(const std::vector<double>& differences) {
  std::vector<double> magnitudes;
  for (double d : differences) {
    if (d == 0.0) return true;
    magnitudes.push_back(std::fabs(d));
  }
  std::sort(magnitudes.begin(), magnitudes.end());
  return std::adjacent_find(magnitudes.begin(), magnitudes.end()) != magnitudes.end();
}

}  // namespace

TEST_CASE("Signed-rank p-values equal SciPy's in approx mode, with and without continuity correction",
          "[stats]") {
  REQUIRE(kStatsReferenceCases.size() >= 10);
  for (const auto& reference : kStatsReferenceCases) {
    INFO("case " << reference.name);
    const auto corrected = wilcoxonSignedRank(reference.differences, {SignedRankMode::Approx, true});
    const auto plain = wilcoxonSignedRank(reference.differences, {SignedRankMode::Approx, false});
    CHECK(corrected.statistic == reference.statistic);
    CHECK_FALSE(corrected.exact);
    CHECK(corrected.p_value == Approx(reference.approx_corrected_p).epsilon(kRelative));
    CHECK(plain.p_value == Approx(reference.approx_uncorrected_p).epsilon(kRelative));
  }
}

TEST_CASE("Exact signed-rank p-values equal SciPy's exact ones on untied differences, zeros dropped",
          "[stats]") {
  int compared = 0;
  for (const auto& reference : kStatsReferenceCases) {
    if (reference.exact_p < 0.0) continue;
    INFO("case " << reference.name);
    const auto exact = wilcoxonSignedRank(reference.differences, {SignedRankMode::Exact, true});
    CHECK(exact.exact);
    CHECK(exact.p_value == Approx(reference.exact_p).epsilon(kRelative));
    ++compared;
  }
  CHECK(compared >= 6);
}

TEST_CASE("Auto mode is exact for at most 50 untied non-zero differences, else the corrected approximation",
          "[stats]") {
  for (const auto& reference : kStatsReferenceCases) {
    INFO("case " << reference.name);
    const auto automatic = wilcoxonSignedRank(reference.differences);
    std::size_t non_zero = 0;
    for (double d : reference.differences) non_zero += d != 0.0 ? 1 : 0;
    std::vector<double> kept;
    for (double d : reference.differences)
      if (d != 0.0) kept.push_back(d);
    const bool exact = !tiedOrZero(kept) && non_zero <= 50;
    CHECK(automatic.exact == exact);
    CHECK(automatic.used == non_zero);
    CHECK(automatic.p_value ==
          Approx(exact ? reference.exact_p : reference.approx_corrected_p).epsilon(kRelative));
  }
}

TEST_CASE("The signed-rank test refuses exact mode on ties, all-zero and non-finite differences", "[stats]") {
  CHECK_THROWS_WITH(wilcoxonSignedRank({1.0, 1.0, 2.0}, {SignedRankMode::Exact, true}),
                    Catch::Contains("untied"));
  CHECK_THROWS_WITH(wilcoxonSignedRank({0.0, 0.0}), Catch::Contains("every difference is zero"));
  CHECK_THROWS_WITH(wilcoxonSignedRank({1.0, NAN}), Catch::Contains("value 1 is not finite"));
}

TEST_CASE("Sign-test p-values equal SciPy's binomtest, zeros dropped", "[stats]") {
  for (const auto& reference : kStatsReferenceCases) {
    INFO("case " << reference.name);
    CHECK(signTest(reference.differences).p_value == Approx(reference.sign_p).epsilon(kRelative));
  }
  CHECK(binomialHalfCdf(1, 4) == Approx(5.0 / 16.0).epsilon(1e-14));
  const auto none = signTest({0.0, 0.0, 0.0});
  CHECK(none.positive + none.negative == 0);
  CHECK(none.p_value == 1.0);
}

TEST_CASE("Effect sizes: mean and median difference, matched-pairs rank-biserial correlation", "[stats]") {
  const auto all_positive = pairedEffectSize({1.0, 2.0, 3.0});
  CHECK(all_positive.rank_biserial == 1.0);
  CHECK(all_positive.mean_difference == 2.0);
  CHECK(all_positive.median_difference == 2.0);
  const auto alternating = pairedEffectSize({1.0, -2.0, 3.0, -4.0});  // W+ = 1 + 3, W- = 2 + 4
  CHECK(alternating.rank_biserial == Approx(-0.2).epsilon(1e-15));
  CHECK(alternating.median_difference == -0.5);
  CHECK(alternating.mean_difference == -0.5);
  const auto with_zeros = pairedEffectSize({0.0, 0.0, 1.0, -1.0, 2.0});  // ranks 1.5, 1.5, 3: W+ 4.5, W- 1.5
  CHECK(with_zeros.rank_biserial == Approx(0.5).epsilon(1e-15));
  CHECK(with_zeros.median_difference == 0.0);
  CHECK(with_zeros.mean_difference == Approx(0.4).epsilon(1e-15));
  CHECK(pairedEffectSize({0.0, 0.0}).rank_biserial == 0.0);
  for (const auto& reference : kStatsReferenceCases) {
    const auto test = wilcoxonSignedRank(reference.differences);
    CHECK(pairedEffectSize(reference.differences).rank_biserial ==
          Approx((test.w_plus - test.w_minus) / (test.w_plus + test.w_minus)).epsilon(1e-15));
  }
  CHECK_THROWS_AS(pairedEffectSize({}), std::invalid_argument);
}

TEST_CASE("tools/stats_reference.py still prints the committed reference values", "[stats]") {
  occsweep::test::requireReferenceScriptUnchanged("stats_reference",
                                                 "import scipy; assert scipy.__version__ == \"1.10.1\"",
                                                 "SciPy 1.10.1");
}
