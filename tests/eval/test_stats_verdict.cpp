// The verdict rules (docs/statistics.md, "Verdicts"): Holm's correction against hand-computed values and against the
// step-down procedure it stands for, and against statsmodels (tools/verdict_reference.py): multipletests for
// Holm, ttost_paired for the negligible rule; the smallest p-value a sample can give; the exact test chosen; each rule.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "occsweep/core/splitmix64.hpp"
#include "occsweep/stats/bootstrap.hpp"
#include "occsweep/stats/multiple_testing.hpp"
#include "occsweep/stats/sign_test.hpp"
#include "occsweep/stats/verdict.hpp"
#include "occsweep/stats/wilcoxon.hpp"
#include "reference_script_check.hpp"
#include "test_helpers.hpp"
#include "verdict_reference_cases.hpp"

using namespace occsweep::stats;
using occsweep::SplitMix64;

namespace {

// Holm's step-down procedure as Holm wrote it: with the p-values sorted, reject H_(1), H_(2), ... while
// p_(i) <= alpha / (m - i + 1), and stop at the first that is not. The oracle for the adjusted p-values.
std::vector<bool> holmRejects(const std::vector<double>& p, double alpha) {
  std::vector<std::size_t> order(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return p[a] < p[b]; });
  std::vector<bool> reject(p.size(), false);
  for (std::size_t i = 0; i < order.size(); ++i) {
    if (p[order[i]] > alpha / double(p.size() - i)) break;
    reject[order[i]] = true;
  }
  return reject;
}

VerdictEvidence evidence(BootstrapInterval interval, std::vector<double> differences, double holm_p,
                         std::size_t family = 1, double smallest_possible_holm_p = NAN) {
  VerdictEvidence e;
  e.differences = differences;
  e.interval = interval;
  e.smallest_possible_holm_p = smallest_possible_holm_p;
  if (std::any_of(differences.begin(), differences.end(), [](double d) { return d != 0; }))
    e.test = exactPairedTest(differences);
  e.holm_p = holm_p;
  e.family = family;
  return e;
}

}  // namespace

TEST_CASE("Holm over three methods: hand-computed adjusted p-values", "[stats]") {
  // Sorted 0.01, 0.03, 0.04: 3 x 0.01 = 0.03; max(0.03, 2 x 0.03) = 0.06; max(0.06, 1 x 0.04) = 0.06.
  const std::vector<double> adjusted = holmAdjusted({0.01, 0.04, 0.03});
  CHECK(adjusted[0] == Approx(0.03).epsilon(1e-15));
  CHECK(adjusted[1] == Approx(0.06).epsilon(1e-15));
  CHECK(adjusted[2] == Approx(0.06).epsilon(1e-15));
  // Capped at 1, and equal p-values stay equal.
  const std::vector<double> capped = holmAdjusted({0.4, 0.4, 0.9});
  CHECK(capped[0] == 1.0);
  CHECK(capped[1] == 1.0);
  CHECK(capped[2] == 1.0);
  CHECK(holmAdjusted({0.02, 0.02})[0] == Approx(0.04).epsilon(1e-15));
  CHECK(holmAdjusted({0.02, 0.02})[1] == Approx(0.04).epsilon(1e-15));
  CHECK(holmAdjusted({}).empty());
  CHECK_THROWS_WITH(holmAdjusted({0.1, NAN}), Catch::Contains("p-value 1"));
  CHECK_THROWS_WITH(holmAdjusted({1.5}), Catch::Contains("p-value 0"));
}

TEST_CASE("Holm-adjusted p-values equal statsmodels' multipletests(method=holm), ties and ones included", "[stats]") {
  for (const auto& reference : occsweep::test::kHolmReferenceCases) {
    INFO(reference.name);
    const std::vector<double> adjusted = holmAdjusted(reference.p_values);
    REQUIRE(adjusted.size() == reference.adjusted.size());
    for (std::size_t i = 0; i < adjusted.size(); ++i) CHECK(adjusted[i] == Approx(reference.adjusted[i]).epsilon(1e-12));
  }
}

TEST_CASE("negligible exactly when statsmodels' ttost_paired rejects at alpha 0.05 with +-0.1", "[stats]") {
  for (const auto& reference : occsweep::test::kTostReferenceCases) {
    INFO(reference.name << ": TOST p = " << reference.p_value);
    REQUIRE(std::fabs(reference.p_value - 0.05) > 1e-6);  // no case on the edge, where rounding could decide
    const Verdict v = decideVerdict(evidence({-1, -1, 1}, reference.differences, 1.0), {0.05, 0.1});
    CHECK((v.kind == VerdictKind::Negligible) == (reference.p_value <= 0.05));
  }
}

TEST_CASE("tools/verdict_reference.py still prints the committed reference values", "[stats]") {
  occsweep::test::requireReferenceScriptUnchanged("verdict_reference",
                                                 "import statsmodels, scipy; assert scipy.__version__ == \"1.10.1\"",
                                                 "statsmodels and SciPy 1.10.1");
}

TEST_CASE("Holm: an adjusted p-value is at most alpha exactly when the step-down procedure rejects", "[stats]") {
  SplitMix64 rng(28);
  for (int seed = 0; seed < 500; ++seed) {
    const std::size_t m = 1 + rng.below(8);
    std::vector<double> p(m);
    for (double& v : p) v = double(rng.below(1001)) / 1000.0 * (rng.below(2) ? 0.1 : 1.0);  // ties and small values
    const double alpha = 0.01 + 0.09 * rng.uniform();
    const std::vector<double> adjusted = holmAdjusted(p);
    const std::vector<bool> reject = holmRejects(p, alpha);
    for (std::size_t i = 0; i < m; ++i) {
      INFO("seed " << seed << " p " << p[i] << " alpha " << alpha);
      CHECK((adjusted[i] <= alpha) == reject[i]);
      CHECK(adjusted[i] >= p[i]);
    }
  }
}

TEST_CASE("The smallest p-value n non-zero differences can give is that of n of one sign", "[stats]") {
  CHECK(smallestPossibleP(0) == 1.0);
  CHECK(smallestPossibleP(1) == 1.0);
  CHECK(smallestPossibleP(2) == 0.5);
  CHECK(smallestPossibleP(4) == 0.125);
  CHECK(smallestPossibleP(5) == 0.0625);
  CHECK(smallestPossibleP(6) == 0.03125);
  for (std::size_t n = 1; n <= 20; ++n) {
    std::vector<double> all_positive;
    for (std::size_t i = 0; i < n; ++i) all_positive.push_back(double(i + 1));
    INFO("n = " << n);
    CHECK(signTest(all_positive).p_value == Approx(smallestPossibleP(n)).epsilon(1e-12));
    CHECK(wilcoxonSignedRank(all_positive, {SignedRankMode::Exact, false}).p_value ==
          Approx(smallestPossibleP(n)).epsilon(1e-12));
  }
}

TEST_CASE("The exact test: Wilcoxon's where its exact distribution applies, else the sign test", "[stats]") {
  const std::vector<double> untied{0.3, -0.1, 0.5, 0.7, 0.2, 0.0, 0.9};
  const ExactPairedTest w = exactPairedTest(untied);
  CHECK(w.name == "Wilcoxon signed-rank, exact");
  CHECK(w.nonzero == 6);
  CHECK(w.p_value == wilcoxonSignedRank(untied, {SignedRankMode::Exact, false}).p_value);
  const std::vector<double> tied{0.3, -0.3, 0.5, 0.5, 0.2};
  const ExactPairedTest s = exactPairedTest(tied);
  CHECK(s.name == "sign test, exact");
  CHECK(s.p_value == signTest(tied).p_value);
  CHECK_THROWS_WITH(exactPairedTest({0.0, 0.0}), Catch::Contains("every difference is zero"));
}

TEST_CASE("Verdict rules, each on its own", "[stats]") {
  const BootstrapInterval positive{1.0, 0.5, 1.5};
  SECTION("two data sets, both better: too few to tell, whatever the interval") {
    const Verdict v = decideVerdict(evidence(positive, {1.0, 1.2}, 0.5));
    CHECK(v.kind == VerdictKind::TooFew);
    CHECK(v.text == "too few data sets to tell (n = 2; the smallest p possible is 0.5)");
  }
  SECTION("four data sets, all better: p = 0.125 is the smallest four can give") {
    const Verdict v = decideVerdict(evidence(positive, {1.0, 1.2, 0.8, 0.9}, 0.125));
    CHECK(v.kind == VerdictKind::TooFew);
    CHECK(v.text.find("0.125") != std::string::npos);
  }
  SECTION("eight data sets, all better: gain, with its sample, test and correction named") {
    const std::vector<double> d{1.0, 1.2, 0.8, 0.9, 1.1, 0.7, 1.3, 0.6};
    const Verdict v = decideVerdict(evidence(positive, d, exactPairedTest(d).p_value));
    CHECK(v.kind == VerdictKind::Gain);
    CHECK(v.text == "gain");
    CHECK(v.basis.find("n = 8 data sets") != std::string::npos);
    CHECK(v.basis.find("Wilcoxon signed-rank, exact p = 0.00781") != std::string::npos);
    CHECK(v.basis.find("Holm-adjusted over 1 comparison") != std::string::npos);
  }
  SECTION("after Holm over three methods: a gain at an adjusted p of 0.023, not at 0.06") {
    const std::vector<double> d{1.0, 1.2, 0.8, 0.9, 1.1, 0.7, 1.3, 0.6};
    CHECK(decideVerdict(evidence(positive, d, 3 * 0.0078125, 3)).kind == VerdictKind::Gain);
    CHECK(decideVerdict(evidence(positive, d, 0.06, 3)).kind == VerdictKind::NoClearDifference);
  }
  SECTION("six data sets all worse, interval below 0: loss") {
    const std::vector<double> d{-1.0, -1.2, -0.8, -0.9, -1.1, -0.7};
    CHECK(decideVerdict(evidence({-1.0, -1.3, -0.7}, d, 0.03125)).kind == VerdictKind::Loss);
  }
  SECTION("-0.004 % with a tight interval: negligible, not loss, whatever the p-value") {
    std::vector<double> d;
    for (int i = 0; i < 20; ++i) d.push_back(-0.004 - 0.0001 * i);
    const Verdict v = decideVerdict(evidence({-0.005, -0.006, -0.004}, d, 1e-6));
    CHECK(v.kind == VerdictKind::Negligible);
    CHECK(v.text.find("negligible (TOST: the 90% t interval [") == 0);
    CHECK(v.text.find("lies within +-0.1 %)") != std::string::npos);
    REQUIRE(v.equivalence);
    CHECK(v.equivalence->level == Approx(0.9));
  }
  SECTION("an interval that reaches past the smallest effect is not negligible") {
    const std::vector<double> d{-0.05, -0.2, -0.1, -0.15, -0.12, -0.08};
    CHECK(decideVerdict(evidence({-0.12, -0.18, -0.06}, d, 0.03125)).kind == VerdictKind::Loss);
  }
  SECTION("an interval containing 0: no clear difference") {
    const std::vector<double> d{1.0, -1.2, 0.8, -0.9, 1.1, -0.7};
    CHECK(decideVerdict(evidence({0.0, -0.8, 0.8}, d, 0.8)).kind == VerdictKind::NoClearDifference);
  }
  SECTION("an interval excluding 0 with a test that does not reject: no clear difference") {
    const std::vector<double> d{1.0, -0.2, 0.8, 0.9, -0.1, 0.7};
    CHECK(decideVerdict(evidence({0.5, 0.1, 0.9}, d, 0.16)).kind == VerdictKind::NoClearDifference);
  }
  SECTION("every data set equal: a tie") {
    const Verdict v = decideVerdict(evidence({0, 0, 0}, {0, 0, 0, 0, 0, 0, 0}, 1.0));
    CHECK(v.kind == VerdictKind::Tie);
    CHECK(v.text == "tie (equal on all 7 data sets)");
  }
  SECTION("six data sets of which three differ: too few, with the smallest p of three") {
    const Verdict v = decideVerdict(evidence(positive, {1.0, 0, 1.2, 0, 0.8, 0}, 0.25));
    CHECK(v.kind == VerdictKind::TooFew);
    CHECK(v.text.find("0.25") != std::string::npos);
    CHECK(v.basis.find("(3 non-zero)") != std::string::npos);
  }
  SECTION("one data set: too few, named in the singular") {
    const Verdict v = decideVerdict(evidence(positive, {1.0}, 1.0));
    CHECK(v.kind == VerdictKind::TooFew);
    CHECK(v.basis.find("n = 1 data set") == 0);
    CHECK(v.basis.find("n = 1 data sets") == std::string::npos);
  }
  SECTION("Holm decides whether the sample can reject: six data sets all better in a family of three") {
    // 2 / 2^6 = 0.03125 <= 0.05 alone, but Holm multiplies the least p of the family by 3: 0.09375 > 0.05.
    const std::vector<double> d{1.0, 1.2, 0.8, 0.9, 1.1, 0.7};
    const double bound = smallestPossibleHolmP({0.03125, 0.03125, 0.03125}, 0);
    CHECK(bound == Approx(0.09375).epsilon(1e-15));
    const Verdict v = decideVerdict(evidence(positive, d, 3 * 0.03125, 3, bound));
    CHECK(v.kind == VerdictKind::TooFew);
    CHECK(v.text == "too few data sets to tell (n = 6; the smallest p possible is 0.0938 after Holm's correction "
                    "over 3 comparisons)");
    CHECK(decideVerdict(evidence(positive, d, 0.03125, 1)).kind == VerdictKind::Gain);
  }
  SECTION("Holm's bound is the family's adjusted smallest p-values: a comparison on 6 can pass beside one on 8") {
    // Ranked second of two behind a p of 2 / 2^8: adjusted max(2 x 0.0078125, 1 x 0.03125) = 0.03125.
    const std::vector<double> d{1.0, 1.2, 0.8, 0.9, 1.1, 0.7};
    CHECK(smallestPossibleHolmP({0.0078125, 0.03125}, 1) == 0.03125);
    CHECK(smallestPossibleHolmP({1.0, 0.03125}, 1) == 0.0625);
    CHECK(decideVerdict(evidence(positive, d, 0.03125, 2, 0.03125)).kind == VerdictKind::Gain);
    CHECK(decideVerdict(evidence(positive, d, 0.0625, 2, 0.0625)).kind == VerdictKind::TooFew);
  }
  SECTION("Holm's bound counts every multiplier up to the comparison's rank: 8, 6 and 6 data sets give 0.0625") {
    // Sorted 2/2^8, 2/2^6, 2/2^6: 3 x 0.0078125 = 0.0234; max(0.0234, 2 x 0.03125) = 0.0625; max(0.0625, 0.03125).
    // (A bound from the family's least p alone, max(own, 3 x least) = 0.03125, would let both six pass.)
    const std::vector<double> smallest{0.0078125, 0.03125, 0.03125};
    CHECK(smallestPossibleHolmP(smallest, 0) == Approx(0.0234375).epsilon(1e-15));
    CHECK(smallestPossibleHolmP(smallest, 1) == Approx(0.0625).epsilon(1e-15));
    CHECK(smallestPossibleHolmP(smallest, 2) == Approx(0.0625).epsilon(1e-15));
    CHECK(smallestPossibleHolmP({0.0078125, 0.03125, 0.03125, 0.03125}, 3) == Approx(0.09375).epsilon(1e-15));
    const std::vector<double> d{1.0, 1.2, 0.8, 0.9, 1.1, 0.7};
    const Verdict v = decideVerdict(evidence(positive, d, 0.0625, 3, smallestPossibleHolmP(smallest, 1)));
    CHECK(v.kind == VerdictKind::TooFew);
    CHECK(v.text.find("the smallest p possible is 0.0625 after Holm's correction over 3 comparisons") !=
          std::string::npos);
    CHECK_THROWS_WITH(smallestPossibleHolmP(smallest, 3), Catch::Contains("index 3 of a family of 3"));
  }
  SECTION("a mean below 0 from a few large losses while most data sets gain: not a loss (old: loss)") {
    // 33 of 40 better by about 6 %, 7 worse by 80-93 %: the mean and its interval are negative, but the signed-rank
    // statistic leans positive (W+ > W-), and its two-sided p is small.
    std::vector<double> d;
    for (int i = 0; i < 33; ++i) d.push_back(5.0 + 0.05 * i);
    for (int i = 0; i < 7; ++i) d.push_back(-80.0 - 2.0 * i);
    const ExactPairedTest t = exactPairedTest(d);
    CHECK(t.direction == 1);
    const Verdict v = decideVerdict(evidence({-24.3, -16.0, -0.5}, d, t.p_value));
    INFO(v.text << " p = " << t.p_value);
    REQUIRE(t.p_value <= 0.05);
    CHECK(v.kind == VerdictKind::NoClearDifference);
    CHECK(v.text.find("point opposite ways") != std::string::npos);
  }
  SECTION("equal differences: the interval [d, d], negligible within the smallest effect, as nearly equal ones") {
    const std::vector<double> equal(8, 0.001), nearly{0.001, 0.001, 0.001, 0.001, 0.001, 0.001, 0.001, 0.0010001};
    CHECK(decideVerdict(evidence({0.001, 0.001, 0.001}, equal, 0.0078125)).kind == VerdictKind::Negligible);
    CHECK(decideVerdict(evidence({0.001, 0.001, 0.001}, nearly, 0.0078125)).kind == VerdictKind::Negligible);
    CHECK(decideVerdict(evidence({0.5, 0.5, 0.5}, std::vector<double>(8, 0.5), 0.0078125)).kind == VerdictKind::Gain);
  }
  SECTION("seven of eight data sets equal, the eighth -0.004 %: negligible, not too few") {
    const Verdict v = decideVerdict(evidence({-0.0005, -0.001, 0.0}, {0, 0, 0, 0, -0.004, 0, 0, 0}, 1.0));
    CHECK(v.kind == VerdictKind::Negligible);
  }
  SECTION("negligible rests on the t interval, not the bootstrap's: a BCa interval within +-0.1 is not enough") {
    // Six differences whose 90% t interval reaches past 0.1 while a (too narrow) bootstrap interval would not.
    const std::vector<double> d{0.02, 0.11, 0.0, 0.12, 0.03, 0.1};
    const MeanTInterval t = meanTInterval(d, 0.9);
    REQUIRE(t.upper > 0.1);
    const Verdict v = decideVerdict(evidence({0.063, 0.03, 0.095}, d, 0.03125));
    CHECK(v.kind != VerdictKind::Negligible);
  }
  SECTION("the equivalence test is Bonferroni-corrected over the family: 1 - 2 alpha / 3") {
    std::vector<double> d;
    for (int i = 0; i < 20; ++i) d.push_back(-0.004 - 0.0001 * i);
    const Verdict v = decideVerdict(evidence({-0.005, -0.006, -0.004}, d, 1e-6, 3));
    REQUIRE(v.equivalence);
    CHECK(v.equivalence->level == Approx(1 - 0.1 / 3));
  }
  SECTION("alpha and the smallest effect are the caller's") {
    const std::vector<double> d{1.0, 1.2, 0.8, 0.9, 1.1, 0.7};
    CHECK(decideVerdict(evidence(positive, d, 0.03125), {0.01, 0.1}).kind == VerdictKind::TooFew);
    CHECK(decideVerdict(evidence(positive, d, 0.03125), {0.05, 2.0}).kind == VerdictKind::Negligible);
  }
}
