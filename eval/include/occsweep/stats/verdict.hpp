// The verdict on a paired comparison of two methods: "gain", "loss", "negligible", "tie", "no clear difference" or
// "too few to tell", by the rules of docs/statistics.md ("Verdicts"): an interval that excludes 0 is not enough; the
// exact test must reject after Holm's correction, and the sample must be able to reject at all.
#pragma once

#include <cstddef>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "occsweep/stats/bootstrap.hpp"
#include "occsweep/stats/sign_test.hpp"

namespace occsweep::stats {

struct VerdictRules {
  double alpha = 0.05;            ///< family-wise, over the methods compared with one baseline (Holm)
  double smallest_effect = 0.1;   ///< in the interval's unit (percent of the baseline's AUC): within +-this is negligible
};

/// The exact paired test a verdict rests on: Wilcoxon's signed-rank test where its exact null distribution applies
/// (untied non-zero |differences|, at most 1,000 of them), otherwise the sign test. Zeros are dropped by both.
struct ExactPairedTest {
  std::string name;               ///< "Wilcoxon signed-rank, exact" or "sign test, exact"
  double p_value = 1.0;           ///< two-sided
  std::size_t nonzero = 0;        ///< the differences the test uses
  double smallest_possible_p = 1.0;  ///< the least p-value `nonzero` differences can give (smallestPossibleP)
  /// The side the test's statistic leans to: +1 when the positive differences outweigh the negative ones (Wilcoxon:
  /// W+ > W-; sign test: more positive), -1 the other way, 0 balanced. A gain or loss needs it on the interval's side.
  int direction = 0;
};

/// Throws std::invalid_argument on a non-finite difference or when every difference is zero (no test is possible).
[[nodiscard]] ExactPairedTest exactPairedTest(const std::vector<double>& differences);

/// The least two-sided p-value of the exact sign or signed-rank test on n non-zero differences: all n of one sign,
/// 2 / 2^n (1 for n <= 1). Below alpha only from n = 6 on at alpha = 0.05 (0.03125).
[[nodiscard]] double smallestPossibleP(std::size_t nonzero);

/// NotComputed is the caller's, where the evidence itself could not be had; decideVerdict never returns it.
enum class VerdictKind { Gain, Loss, Negligible, Tie, NoClearDifference, TooFew, NotComputed };

/// What a comparison shows, over paired units (data sets): their differences, the bootstrap interval of the mean
/// difference, the exact test (none when every difference is zero) and its p-value after Holm's correction over a
/// family of `family` comparisons.
struct VerdictEvidence {
  std::vector<double> differences;  ///< one per unit, in `value_unit`
  std::string unit_name = "data sets";
  std::string value_unit = "%";  ///< of the differences and the interval (percent of the baseline's AUC)
  std::optional<BootstrapInterval> interval;
  double interval_level = 0.95;  ///< the bootstrap interval's coverage (BCa)
  std::optional<ExactPairedTest> test;
  double holm_p = 1.0;
  std::size_t family = 1;
  /// The least Holm-adjusted p this comparison can reach in its family (smallestPossibleHolmP); NaN: its own
  /// test's smallest possible p, as in a family of one.
  double smallest_possible_holm_p = std::numeric_limits<double>::quiet_NaN();
  /// The same were every unit non-zero (smallestPossibleP of the units' count): the minimum below which no verdict,
  /// "negligible" included, is decided. NaN: smallestPossibleP(units), as in a family of one.
  double smallest_possible_holm_p_of_units = std::numeric_limits<double>::quiet_NaN();
};

/// The least Holm-adjusted p-value comparison `index` of a family can reach, given each comparison's smallest
/// possible p (smallestPossibleP; 1 for one without a test). Holm's adjusted p-values never fall when a p-value
/// rises, and each comparison can reach its smallest p at once (all its values of one sign), so the least is
/// holmAdjusted(smallest_possible_p)[index], and it is reached (docs/statistics.md, "Verdicts").
[[nodiscard]] double smallestPossibleHolmP(const std::vector<double>& smallest_possible_p, std::size_t index);

struct Verdict {
  VerdictKind kind = VerdictKind::TooFew;
  /// The equivalence test's interval: the sign test's interval of the median at 1 - 2 alpha / family, where the
  /// units are enough to reach that level.
  std::optional<MedianInterval> equivalence;
  /// What is printed: "gain", "loss", "negligible median difference (...)", "tie (...)", "no clear difference",
  /// "too few ..."
  std::string text;
  std::string basis;  ///< its sample, test and correction, in one sentence
};

/// The rules, in order (docs/statistics.md, "Verdicts"): every difference of 2 or more units zero: tie; units
/// too few for any p-value to reach alpha (after Holm): too few to tell; the Holm-adjusted p at most alpha: gain or
/// loss when the bootstrap interval excludes 0 and the test leans its way ("below the smallest effect" when the
/// difference is also shown negligible), else no clear difference; the median's interval (sign test, Bonferroni
/// over the family) and the bootstrap interval both within +-smallest_effect: negligible median difference;
/// non-zero differences too few to reject: no clear difference, saying how many differ; otherwise no clear
/// difference. TooFew is rule 3 alone: the units themselves are too few.
[[nodiscard]] Verdict decideVerdict(const VerdictEvidence& evidence, const VerdictRules& rules = {});

}  // namespace occsweep::stats
