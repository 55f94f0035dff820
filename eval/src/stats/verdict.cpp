#include "occsweep/stats/verdict.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "occsweep/stats/multiple_testing.hpp"
#include "occsweep/stats/sign_test.hpp"
#include "occsweep/stats/wilcoxon.hpp"
#include "sample_checks.hpp"

namespace occsweep::stats {
namespace {

// 2 / 2^n underflows no double below this n; above it the smallest p is reported as 2^-1099, already ~0.
constexpr std::size_t kSmallestPCount = 1100;

bool tiedMagnitudes(std::vector<double> nonzero) {
  for (double& v : nonzero) v = std::fabs(v);
  std::sort(nonzero.begin(), nonzero.end());
  return std::adjacent_find(nonzero.begin(), nonzero.end()) != nonzero.end();
}

// "data set" for "data sets": the unit's name for n = 1.
std::string singular(const std::string& plural) {
  return plural.size() > 1 && plural.back() == 's' ? plural.substr(0, plural.size() - 1) : plural;
}

std::string number(double v, const char* format) {
  char buf[48];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

std::string sampleText(const VerdictEvidence& e) {
  const std::size_t n = e.differences.size();
  std::string s = "n = " + std::to_string(n) + " " + (n == 1 ? singular(e.unit_name) : e.unit_name);
  if (e.test && e.test->nonzero < n) s += " (" + std::to_string(e.test->nonzero) + " non-zero)";
  return s;
}

std::string intervalText(const VerdictEvidence& e) {
  const BootstrapInterval& i = *e.interval;
  return "mean " + number(i.estimate, "%+.3g") + " " + e.value_unit + ", " + number(e.interval_level * 100, "%g") +
         "% BCa interval [" + number(i.lower, "%+.3g") + ", " + number(i.upper, "%+.3g") + "]";
}

std::string testText(const VerdictEvidence& e, const VerdictRules& r) {
  const ExactPairedTest& t = *e.test;
  return t.name + " p = " + number(t.p_value, "%.3g") + ", Holm-adjusted over " + std::to_string(e.family) +
         (e.family == 1 ? " comparison " : " comparisons ") + number(e.holm_p, "%.3g") + " (alpha " +
         number(r.alpha, "%g") + ")";
}

std::string basisText(const VerdictEvidence& e, const VerdictRules& r) {
  std::string s = sampleText(e);
  if (e.interval) s += "; " + intervalText(e);
  if (e.test) s += "; " + testText(e, r);
  return s;
}

std::string equivalenceText(const MeanTInterval& t, const VerdictEvidence& e, const VerdictRules& r) {
  return "TOST: the " + number(t.level * 100, "%.4g") + "% t interval [" + number(t.lower, "%+.3g") + ", " +
         number(t.upper, "%+.3g") + "] " + e.value_unit + " lies within +-" + number(r.smallest_effect, "%g") + " " +
         e.value_unit;
}

// The equivalence test (two one-sided t tests at alpha each, Bonferroni over the family): the mean's t interval at
// 1 - 2 alpha / family within +-smallest_effect.
std::optional<MeanTInterval> equivalenceInterval(const VerdictEvidence& e, const VerdictRules& r) {
  if (e.differences.size() < 2) return std::nullopt;
  // Equal differences give the interval [d, d], the limit of the t interval as the spread goes to zero: negligible
  // exactly when |d| is within the smallest effect, with no jump between equal and nearly equal values.
  const double level = 1.0 - 2.0 * r.alpha / double(std::max<std::size_t>(e.family, 1));
  if (!(level > 0.0)) return std::nullopt;
  return meanTInterval(e.differences, level);
}

Verdict tooFew(const VerdictEvidence& e, const VerdictRules& r, double smallest_p) {
  const std::size_t n = e.differences.size();
  std::string bound = "the smallest p possible is " + number(smallest_p, "%.3g");
  if (e.family > 1 && n >= 2) bound += " after Holm's correction over " + std::to_string(e.family) + " comparisons";
  return {VerdictKind::TooFew, std::nullopt,
          "too few " + e.unit_name + " to tell (n = " + std::to_string(n) + "; " + bound + ")", basisText(e, r)};
}

}  // namespace

double smallestPossibleP(std::size_t nonzero) {
  return nonzero <= 1 ? 1.0 : std::ldexp(1.0, 1 - int(std::min(nonzero, kSmallestPCount)));
}

ExactPairedTest exactPairedTest(const std::vector<double>& differences) {
  detail::requireFinite(differences, "exact paired test");
  const std::vector<double> nonzero = detail::nonZero(differences);
  if (nonzero.empty()) throw std::invalid_argument("exact paired test: every difference is zero");
  ExactPairedTest t;
  t.nonzero = nonzero.size();
  t.smallest_possible_p = smallestPossibleP(t.nonzero);
  if (t.nonzero <= kMaxExactSignedRankCount && !tiedMagnitudes(nonzero)) {
    t.name = "Wilcoxon signed-rank, exact";
    const SignedRankResult w = wilcoxonSignedRank(nonzero, {SignedRankMode::Exact, false});
    t.p_value = w.p_value;
    t.direction = (w.w_plus > w.w_minus) - (w.w_plus < w.w_minus);
  } else {
    t.name = "sign test, exact";
    const SignTestResult s = signTest(nonzero);
    t.p_value = s.p_value;
    t.direction = (s.positive > s.negative) - (s.positive < s.negative);
  }
  return t;
}

double smallestPossibleHolmP(const std::vector<double>& smallest_possible_p, std::size_t index) {
  if (index >= smallest_possible_p.size())
    throw std::invalid_argument("smallestPossibleHolmP: index " + std::to_string(index) + " of a family of " +
                                std::to_string(smallest_possible_p.size()));
  return holmAdjusted(smallest_possible_p)[index];
}

Verdict decideVerdict(const VerdictEvidence& e, const VerdictRules& r) {
  const std::size_t n = e.differences.size();
  if (n < 2) return tooFew(e, r, 1.0);
  if (!e.test)
    return {VerdictKind::Tie, std::nullopt, "tie (equal on all " + std::to_string(n) + " " + e.unit_name + ")",
            basisText(e, r)};
  const std::string basis = basisText(e, r);
  if (const std::optional<MeanTInterval> t = equivalenceInterval(e, r);
      t && t->lower > -r.smallest_effect && t->upper < r.smallest_effect)
    return {VerdictKind::Negligible, t, "negligible (" + equivalenceText(*t, e, r) + ")", basis};
  const double least_p = std::isnan(e.smallest_possible_holm_p) ? e.test->smallest_possible_p
                                                                : e.smallest_possible_holm_p;
  if (least_p > r.alpha) return tooFew(e, r, least_p);
  if (!e.interval) return {VerdictKind::NoClearDifference, std::nullopt, "no clear difference", basis};
  const BootstrapInterval& i = *e.interval;
  if (!i.contains(0.0) && e.holm_p <= r.alpha) {
    const int side = i.lower > 0 ? 1 : -1;
    if (e.test->direction != side)  // e.g. a mean pulled below 0 by a few large losses, most data sets better
      return {VerdictKind::NoClearDifference, std::nullopt,
              "no clear difference (the interval of the mean and the exact test point opposite ways)", basis};
    return {side > 0 ? VerdictKind::Gain : VerdictKind::Loss, std::nullopt, side > 0 ? "gain" : "loss", basis};
  }
  return {VerdictKind::NoClearDifference, std::nullopt, "no clear difference", basis};
}

}  // namespace occsweep::stats
