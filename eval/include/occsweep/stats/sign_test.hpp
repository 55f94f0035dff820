// Two-sided exact sign test (docs/statistics.md).
#pragma once

#include <cstddef>
#include <optional>
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

/// The distribution-free interval of the median, [x_(n-c+1), x_(c)] with c the least count whose binomial tail
/// P(X >= c) is at most (1 - level) / 2: the inversion of the one-sided sign tests, so its coverage is at least
/// `level` for any population, skewed, tied or full of zeros (docs/statistics.md, "Verdicts").
struct MedianInterval {
  double lower = 0, upper = 0;
  double level = 0;  ///< the level asked for; the coverage is at least this
  std::size_t n = 0;
};

/// None when n values cannot reach the level (2^-n above (1 - level) / 2). Throws std::invalid_argument on a
/// non-finite value or a level outside (0, 1).
[[nodiscard]] std::optional<MedianInterval> medianInterval(std::vector<double> values, double level);

}  // namespace occsweep::stats
