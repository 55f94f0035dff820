#include "occsweep/stats/sign_test.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "sample_checks.hpp"

namespace occsweep::stats {

double binomialHalfCdf(std::size_t k, std::size_t n) {
  if (k >= n) return 1.0;
  const double log_half_power = -double(n) * std::log(2.0);
  const double log_n_factorial = std::lgamma(double(n) + 1.0);
  double sum = 0.0;
  for (std::size_t j = 0; j <= k; ++j)
    sum += std::exp(log_n_factorial - std::lgamma(double(j) + 1.0) - std::lgamma(double(n - j) + 1.0) +
                    log_half_power);
  return std::min(1.0, sum);
}

SignTestResult signTest(const std::vector<double>& differences) {
  detail::requireFinite(differences, "sign test");
  SignTestResult result;
  for (double d : differences) {
    if (d > 0.0) ++result.positive;
    if (d < 0.0) ++result.negative;
  }
  // Binomial(n, 1/2) is symmetric, so the two-sided p-value is twice the smaller tail (capped at 1), which is
  // also what SciPy's binomtest sums (outcomes no more likely than the observed one).
  const std::size_t n = result.positive + result.negative;
  result.p_value = std::min(1.0, 2.0 * binomialHalfCdf(std::min(result.positive, result.negative), n));
  return result;
}

std::optional<MedianInterval> medianInterval(std::vector<double> values, double level) {
  detail::requireFinite(values, "median interval");
  if (!(level > 0.0 && level < 1.0)) throw std::invalid_argument("median interval: level must lie in (0, 1)");
  const std::size_t n = values.size();
  const double tail = (1.0 - level) / 2.0;
  // P(X >= c) = P(X <= n - c) by symmetry; the least c whose tail is within `tail`.
  std::size_t c = n / 2 + 1;
  while (c <= n && binomialHalfCdf(n - c, n) > tail) ++c;
  if (c > n) return std::nullopt;
  std::sort(values.begin(), values.end());
  return MedianInterval{values[n - c], values[c - 1], level, n};
}

}  // namespace occsweep::stats
