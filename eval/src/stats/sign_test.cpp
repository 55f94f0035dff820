#include "occsweep/stats/sign_test.hpp"

#include <algorithm>
#include <cmath>

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

}  // namespace occsweep::stats
