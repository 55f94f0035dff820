#include "occsweep/stats/verdict.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "occsweep/stats/sign_test.hpp"
#include "occsweep/stats/wilcoxon.hpp"
#include "sample_checks.hpp"

namespace occsweep::stats {
namespace {

constexpr std::size_t kMaxExactSignedRank = 1000;  // wilcoxonSignedRank's exact limit (docs/statistics.md)

bool tiedMagnitudes(std::vector<double> nonzero) {
  for (double& v : nonzero) v = std::fabs(v);
  std::sort(nonzero.begin(), nonzero.end());
  return std::adjacent_find(nonzero.begin(), nonzero.end()) != nonzero.end();
}

std::string number(double v, const char* format) {
  char buf[48];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

std::string sampleText(const VerdictEvidence& e) {
  std::string s = "n = " + std::to_string(e.units) + " " + e.unit_name;
  if (e.test && e.test->nonzero < e.units) s += " (" + std::to_string(e.test->nonzero) + " not tied)";
  return s;
}

std::string intervalText(const VerdictEvidence& e) {
  const BootstrapInterval& i = *e.interval;
  return "mean " + number(i.estimate, "%+.3g") + " " + e.value_unit + " [" + number(i.lower, "%+.3g") + ", " +
         number(i.upper, "%+.3g") + "]";
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

Verdict tooFew(const VerdictEvidence& e, const VerdictRules& r, double smallest_p) {
  return {VerdictKind::TooFew,
          "too few " + e.unit_name + " to tell (n = " + std::to_string(e.units) + "; the smallest p possible is " +
              number(smallest_p, "%.3g") + ")",
          basisText(e, r)};
}

}  // namespace

double smallestPossibleP(std::size_t nonzero) { return nonzero <= 1 ? 1.0 : std::ldexp(1.0, 1 - int(std::min<std::size_t>(nonzero, 1100))); }

ExactPairedTest exactPairedTest(const std::vector<double>& differences) {
  detail::requireFinite(differences, "exact paired test");
  const std::vector<double> nonzero = detail::nonZero(differences);
  if (nonzero.empty()) throw std::invalid_argument("exact paired test: every difference is zero");
  ExactPairedTest t;
  t.nonzero = nonzero.size();
  t.smallest_possible_p = smallestPossibleP(t.nonzero);
  if (t.nonzero <= kMaxExactSignedRank && !tiedMagnitudes(nonzero)) {
    t.name = "Wilcoxon signed-rank, exact";
    t.p_value = wilcoxonSignedRank(nonzero, {SignedRankMode::Exact, false}).p_value;
  } else {
    t.name = "sign test, exact";
    t.p_value = signTest(nonzero).p_value;
  }
  return t;
}

Verdict decideVerdict(const VerdictEvidence& e, const VerdictRules& r) {
  if (e.units < 2) return tooFew(e, r, 1.0);
  if (!e.test) return {VerdictKind::Tie, "tie (equal on all " + std::to_string(e.units) + " " + e.unit_name + ")", basisText(e, r)};
  if (e.test->smallest_possible_p > r.alpha) return tooFew(e, r, e.test->smallest_possible_p);
  const std::string basis = basisText(e, r);
  if (!e.interval) return {VerdictKind::NoClearDifference, "no clear difference", basis};
  const BootstrapInterval& i = *e.interval;
  if (i.lower > -r.smallest_effect && i.upper < r.smallest_effect)
    return {VerdictKind::Negligible, "negligible (the interval lies within +-" + number(r.smallest_effect, "%g") + " " + e.value_unit + ")", basis};
  if (!i.contains(0.0) && e.holm_p <= r.alpha)
    return i.lower > 0 ? Verdict{VerdictKind::Gain, "gain", basis} : Verdict{VerdictKind::Loss, "loss", basis};
  return {VerdictKind::NoClearDifference, "no clear difference", basis};
}

}  // namespace occsweep::stats
