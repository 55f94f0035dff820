// Two-sided exact sign test (docs/statistics.md).
#pragma once

#include <cstddef>
#include <vector>

namespace occsweep::stats {

struct SignTestResult {
  std::size_t positive = 0;
  std::size_t negative = 0;  ///< zeros are dropped
  double p_value = 1.0;      ///< exact binomial(positive + negative, 1/2), two-sided
};

/// Throws std::invalid_argument on a non-finite difference. No non-zero difference gives p = 1.
[[nodiscard]] SignTestResult signTest(const std::vector<double>& differences);

/// P(X <= k) for X ~ Binomial(n, 1/2), summed in log space.
[[nodiscard]] double binomialHalfCdf(std::size_t k, std::size_t n);

}  // namespace occsweep::stats
