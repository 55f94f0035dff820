#include "occsweep/stats/student_t.hpp"

#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

#include "sample_checks.hpp"

namespace occsweep::stats {
namespace {

// The continued fraction of the incomplete beta function, evaluated by the modified Lentz method (Press et al.,
// Numerical Recipes, 3rd ed., 6.4); converges fast for x < (a + 1) / (a + b + 2).
double betaContinuedFraction(double a, double b, double x) {
  constexpr double kTiny = 1e-300, kEpsilon = 1e-16;
  double c = 1.0, d = 1.0 - (a + b) * x / (a + 1.0);
  if (std::fabs(d) < kTiny) d = kTiny;
  d = 1.0 / d;
  double h = d;
  for (int m = 1; m <= 10000; ++m) {
    const double m2 = 2.0 * m;
    double aa = m * (b - m) * x / ((a + m2 - 1.0) * (a + m2));
    d = 1.0 + aa * d, c = 1.0 + aa / c;
    if (std::fabs(d) < kTiny) d = kTiny;
    if (std::fabs(c) < kTiny) c = kTiny;
    d = 1.0 / d, h *= d * c;
    aa = -(a + m) * (a + b + m) * x / ((a + m2) * (a + m2 + 1.0));
    d = 1.0 + aa * d, c = 1.0 + aa / c;
    if (std::fabs(d) < kTiny) d = kTiny;
    if (std::fabs(c) < kTiny) c = kTiny;
    d = 1.0 / d;
    const double step = d * c;
    h *= step;
    if (std::fabs(step - 1.0) < kEpsilon) break;
  }
  return h;
}

// I_x(a, b), the regularized incomplete beta function, for 0 <= x <= 1.
double regularizedBeta(double a, double b, double x) {
  if (x <= 0.0) return 0.0;
  if (x >= 1.0) return 1.0;
  const double log_front = std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) + a * std::log(x) + b * std::log1p(-x);
  if (x < (a + 1.0) / (a + b + 2.0)) return std::exp(log_front) * betaContinuedFraction(a, b, x) / a;
  return 1.0 - std::exp(log_front) * betaContinuedFraction(b, a, 1.0 - x) / b;
}

void requireDegrees(double df) {
  if (!(df > 0.0) || !std::isfinite(df)) throw std::invalid_argument("Student's t: degrees of freedom must be > 0");
}

}  // namespace

double studentTCdf(double t, double df) {
  requireDegrees(df);
  if (std::isnan(t)) throw std::invalid_argument("Student's t: t is NaN");
  if (std::isinf(t)) return t > 0 ? 1.0 : 0.0;
  const double tail = 0.5 * regularizedBeta(df / 2.0, 0.5, df / (df + t * t));  // P(T > |t|)
  return t >= 0 ? 1.0 - tail : tail;
}

double studentTQuantile(double p, double df) {
  requireDegrees(df);
  if (!(p > 0.0 && p < 1.0)) throw std::invalid_argument("Student's t quantile: p must lie in (0, 1)");
  if (p < 0.5) return -studentTQuantile(1.0 - p, df);
  double lo = 0.0, hi = 1.0;
  while (studentTCdf(hi, df) < p) lo = hi, hi *= 2.0;
  for (int i = 0; i < 200 && hi - lo > std::numeric_limits<double>::epsilon() * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    (studentTCdf(mid, df) < p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

MeanTInterval meanTInterval(const std::vector<double>& values, double level) {
  detail::requireFinite(values, "t interval");
  if (values.size() < 2) throw std::invalid_argument("t interval: needs at least 2 values");
  if (!(level > 0.0 && level < 1.0)) throw std::invalid_argument("t interval: level must lie in (0, 1)");
  const double n = double(values.size());
  const double mean = std::accumulate(values.begin(), values.end(), 0.0) / n;
  double squares = 0;
  for (double v : values) squares += (v - mean) * (v - mean);
  const double half = studentTQuantile((1.0 + level) / 2.0, n - 1.0) * std::sqrt(squares / (n - 1.0) / n);
  return {mean, mean - half, mean + half, level, values.size()};
}

}  // namespace occsweep::stats
