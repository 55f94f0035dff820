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

std::string equivalenceText(const MedianInterval& m, const VerdictEvidence& e, const VerdictRules& r) {
  return "sign test: the " + number(m.level * 100, "%.4g") + "% interval of the median [" + number(m.lower, "%+.3g") +
         ", " + number(m.upper, "%+.3g") + "] " + e.value_unit + " and the mean's interval lie within +-" +
         number(r.smallest_effect, "%g") + " " + e.value_unit;
}

// The equivalence test: the two one-sided sign tests at alpha / family each (Bonferroni), read off the median's
// interval at 1 - 2 alpha / family. The sign test holds its size on any population, skewed, tied or zero-inflated,
// where no test of a mean from a few values can (docs/statistics.md, "Verdicts").
std::optional<MedianInterval> equivalenceInterval(const VerdictEvidence& e, const VerdictRules& r) {
  const double level = 1.0 - 2.0 * r.alpha / double(std::max<std::size_t>(e.family, 1));
  if (!(level > 0.0)) return std::nullopt;
  return medianInterval(e.differences, level);
}

// Negligible needs both the median's interval and the printed interval of the mean within +-smallest_effect: a
// "negligible" beside a printed interval that reaches past the margin would contradict it.
bool withinSmallestEffect(const std::optional<MedianInterval>& m, const VerdictEvidence& e, const VerdictRules& r) {
  const double d = r.smallest_effect;
  return m && m->lower > -d && m->upper < d && (!e.interval || (e.interval->lower > -d && e.interval->upper < d));
}

double leastP(double family_bound, double own) { return std::isnan(family_bound) ? own : family_bound; }

std::string boundText(const VerdictEvidence& e, double smallest_p) {
  std::string bound = "the smallest p possible is " + number(smallest_p, "%.3g");
  if (e.family > 1 && e.differences.size() >= 2)
    bound += " after Holm's correction over " + std::to_string(e.family) + " comparisons";
  return bound;
}

Verdict tooFew(const VerdictEvidence& e, const VerdictRules& r, double smallest_p) {
  return {VerdictKind::TooFew, std::nullopt,
          "too few " + e.unit_name + " to tell (n = " + std::to_string(e.differences.size()) + "; " +
              boundText(e, smallest_p) + ")",
          basisText(e, r)};
}

// Rule 6 where some units are equal: the units could reject, the few that differ cannot. Not "too few scenes
// (n = 8)", which would contradict its own n: what is lacking is differing units (docs/statistics.md, "Verdicts").
Verdict tooFewDiffering(const VerdictEvidence& e, const VerdictRules& r, const std::optional<MedianInterval>& m,
                        double smallest_p) {
  const std::size_t n = e.differences.size(), differing = e.test->nonzero;
  return {VerdictKind::NoClearDifference, m,
          "no clear difference (n = " + std::to_string(n) + " " + e.unit_name + ", " + std::to_string(n - differing) +
              " equal: " + std::to_string(differing) + " differing " +
              (differing == 1 ? singular(e.unit_name) : e.unit_name) + " cannot show a difference; " +
              boundText(e, smallest_p) + ")",
          basisText(e, r)};
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
  const double least_p_of_units = n < 2 ? 1.0 : leastP(e.smallest_possible_holm_p_of_units, smallestPossibleP(n));
  if (n >= 2 && !e.test)  // a description, not an inference: decided first, as before
    return {VerdictKind::Tie, std::nullopt, "tie (equal on all " + std::to_string(n) + " " + e.unit_name + ")",
            basisText(e, r)};
  if (least_p_of_units > r.alpha) return tooFew(e, r, least_p_of_units);
  const std::string basis = basisText(e, r);
  const std::optional<MedianInterval> m = equivalenceInterval(e, r);
  const bool within = withinSmallestEffect(m, e, r);
  if (e.holm_p <= r.alpha) {  // the difference test rejects: the verdict says so, never "negligible"
    if (!e.interval || e.interval->contains(0.0))
      return {VerdictKind::NoClearDifference, m, "no clear difference", basis};
    const int side = e.interval->lower > 0 ? 1 : -1;
    if (e.test->direction != side)  // e.g. a mean pulled below 0 by a few large losses, most data sets better
      return {VerdictKind::NoClearDifference, m,
              "no clear difference (the interval of the mean and the exact test point opposite ways)", basis};
    std::string text = side > 0 ? "gain" : "loss";
    if (within)
      text += ", below the smallest effect of " + number(r.smallest_effect, "%g") + " " + e.value_unit + " (" +
              equivalenceText(*m, e, r) + ")";
    return {side > 0 ? VerdictKind::Gain : VerdictKind::Loss, m, text, basis};
  }
  if (within)  // the sign test's claim is about the median; a mean at the margin can pass (the size table)
    return {VerdictKind::Negligible, m, "negligible median difference (" + equivalenceText(*m, e, r) + ")", basis};
  const double least_p = leastP(e.smallest_possible_holm_p, e.test->smallest_possible_p);
  if (least_p > r.alpha) return e.test->nonzero < n ? tooFewDiffering(e, r, m, least_p) : tooFew(e, r, least_p);
  return {VerdictKind::NoClearDifference, m, "no clear difference", basis};
}

}  // namespace occsweep::stats
