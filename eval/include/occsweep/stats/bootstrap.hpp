// Seeded bootstrap confidence intervals of a mean, percentile and BCa (docs/statistics.md).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace occsweep::stats {

enum class BootstrapMethod {
  Percentile,  ///< quantiles of the resampled means (Efron & Tibshirani 1993, ch. 13)
  BCa,         ///< bias-corrected and accelerated, jackknife acceleration (Efron & Tibshirani 1993, ch. 14)
};

struct BootstrapOptions {
  double level = 0.95;          ///< two-sided coverage, in (0, 1)
  std::size_t resamples = 10000;
  std::uint64_t seed = 1;       ///< SplitMix64 seed: the same seed and values give the same interval
  BootstrapMethod method = BootstrapMethod::BCa;
};

struct BootstrapInterval {
  double estimate = 0.0;  ///< the sample mean
  double lower = 0.0;
  double upper = 0.0;
  [[nodiscard]] bool contains(double value) const { return lower <= value && value <= upper; }
};

/// Confidence interval of the mean of `values` (e.g. paired differences). All values equal gives [v, v].
/// Throws std::invalid_argument on an empty sample, a non-finite value, a level outside (0, 1) or no resamples.
[[nodiscard]] BootstrapInterval bootstrapMeanInterval(const std::vector<double>& values,
                                                      const BootstrapOptions& options = {});

/// The p-quantile of sorted values, linear interpolation between order statistics (Hyndman & Fan type 7).
[[nodiscard]] double sortedQuantile(const std::vector<double>& sorted, double p);

/// Inverse of the standard normal CDF (Acklam's rational approximation refined by one Halley step).
[[nodiscard]] double normalQuantile(double p);

/// Standard normal CDF, through erfc for accuracy in the tails.
[[nodiscard]] double normalCdf(double z);

}  // namespace occsweep::stats
