// Student's t distribution and the t interval of a mean: the former equivalence rule, which docs/statistics.md's
// size table ("Verdicts") measures beside the sign test that replaced it.
#pragma once

#include <cstddef>
#include <vector>

namespace occsweep::stats {

/// P(T <= t) for Student's t with `df` > 0 degrees of freedom, through the regularized incomplete beta function:
/// for t >= 0, 1 - I_{df / (df + t^2)}(df / 2, 1 / 2) / 2 (Abramowitz and Stegun 26.7.1). Throws
/// std::invalid_argument for df <= 0 or a NaN t.
[[nodiscard]] double studentTCdf(double t, double df);

/// The t with P(T <= t) = p, for 0 < p < 1, by bisection on studentTCdf to double precision. Throws
/// std::invalid_argument outside (0, 1) or for df <= 0.
[[nodiscard]] double studentTQuantile(double p, double df);

/// The two-sided t interval of a mean at `level` (mean +- t_{(1 + level) / 2, n - 1} s / sqrt(n)).
struct MeanTInterval {
  double mean = 0, lower = 0, upper = 0;
  double level = 0;
  std::size_t n = 0;
};

/// Throws std::invalid_argument with fewer than 2 values, a non-finite value, or a level outside (0, 1).
[[nodiscard]] MeanTInterval meanTInterval(const std::vector<double>& values, double level);

}  // namespace occsweep::stats
