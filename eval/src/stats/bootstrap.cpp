#include "occsweep/stats/bootstrap.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

#include "occsweep/core/splitmix64.hpp"
#include "sample_checks.hpp"

namespace occsweep::stats {

namespace {

double meanOf(const std::vector<double>& values) {
  return std::accumulate(values.begin(), values.end(), 0.0) / double(values.size());
}

void requireValidOptions(const BootstrapOptions& options) {
  if (!(options.level > 0.0 && options.level < 1.0))
    throw std::invalid_argument("bootstrap: level must be in (0, 1)");
  if (options.resamples == 0) throw std::invalid_argument("bootstrap: resamples must be at least 1");
}

/// The means of `resamples` samples drawn with replacement, sorted ascending.
std::vector<double> sortedResampledMeans(const std::vector<double>& values, std::size_t resamples,
                                         std::uint64_t seed) {
  SplitMix64 rng(seed);
  std::vector<double> means(resamples);
  for (double& mean : means) {
    double sum = 0.0;
    for (std::size_t j = 0; j < values.size(); ++j) sum += values[rng.below(values.size())];
    mean = sum / double(values.size());
  }
  std::sort(means.begin(), means.end());
  return means;
}

/// Bias correction z0 = Phi^-1(share of resampled means below the estimate), ties counted half (Efron &
/// Tibshirani 1993, ch. 14, with mid-p ties), the share kept within [1/(2B), 1 - 1/(2B)] so z0 stays finite.
double biasCorrection(const std::vector<double>& sorted_means, double estimate) {
  const auto below = std::lower_bound(sorted_means.begin(), sorted_means.end(), estimate);
  const auto not_above = std::upper_bound(sorted_means.begin(), sorted_means.end(), estimate);
  const double count = double(sorted_means.size());
  const double share = (double(below - sorted_means.begin()) + 0.5 * double(not_above - below)) / count;
  return normalQuantile(std::clamp(share, 0.5 / count, 1.0 - 0.5 / count));
}

/// Acceleration from the jackknife means (Efron & Tibshirani 1993, ch. 14); 0 when they are all equal.
double jackknifeAcceleration(const std::vector<double>& values) {
  const double n = double(values.size());
  const double sum = std::accumulate(values.begin(), values.end(), 0.0);
  std::vector<double> leave_one_out(values.size());
  for (std::size_t i = 0; i < values.size(); ++i) leave_one_out[i] = (sum - values[i]) / (n - 1.0);
  const double centre = meanOf(leave_one_out);
  double squares = 0.0, cubes = 0.0;
  for (double theta : leave_one_out) {
    const double d = centre - theta;
    squares += d * d;
    cubes += d * d * d;
  }
  return squares > 0.0 ? cubes / (6.0 * std::pow(squares, 1.5)) : 0.0;
}

/// The BCa-adjusted tail probability for the normal quantile z_alpha (Efron & Tibshirani 1993, ch. 14).
double adjustedTail(double z0, double acceleration, double z_alpha) {
  const double shifted = z0 + z_alpha;
  return normalCdf(z0 + shifted / (1.0 - acceleration * shifted));
}

}  // namespace

double normalCdf(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }

double normalQuantile(double p) {
  if (!(p > 0.0 && p < 1.0)) throw std::invalid_argument("normal quantile: p must be in (0, 1)");
  // Acklam's coefficients (relative error 1.15e-9), then one Halley step on erfc for full precision.
  static const double a[] = {-3.969683028665376e+01, 2.209460984245205e+02, -2.759285104469687e+02,
                             1.383577518672690e+02,  -3.066479806614716e+01, 2.506628277459239e+00};
  static const double b[] = {-5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02,
                             6.680131188771972e+01,  -1.328068155288572e+01};
  static const double c[] = {-7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
                             -2.549732539343734e+00, 4.374664141464968e+00,  2.938163982698783e+00};
  static const double d[] = {7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00,
                             3.754408661907416e+00};
  const double low = 0.02425;
  double x;
  if (p < low) {
    const double q = std::sqrt(-2.0 * std::log(p));
    x = (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
        ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1.0);
  } else if (p <= 1.0 - low) {
    const double q = p - 0.5, r = q * q;
    x = (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
        (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1.0);
  } else {
    const double q = std::sqrt(-2.0 * std::log1p(-p));
    x = -(((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
        ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1.0);
  }
  const double e = normalCdf(x) - p;
  const double u = e * std::sqrt(2.0 * M_PI) * std::exp(x * x / 2.0);
  return x - u / (1.0 + x * u / 2.0);
}

double sortedQuantile(const std::vector<double>& sorted, double p) {
  const double position = std::clamp(p, 0.0, 1.0) * double(sorted.size() - 1);
  const auto below = std::size_t(std::floor(position));
  const std::size_t above = std::min(below + 1, sorted.size() - 1);
  const double fraction = position - double(below);
  return sorted[below] + fraction * (sorted[above] - sorted[below]);
}

BootstrapInterval bootstrapMeanInterval(const std::vector<double>& values, const BootstrapOptions& options) {
  detail::requireNonEmpty(values, "bootstrap");
  detail::requireFinite(values, "bootstrap");
  requireValidOptions(options);
  const double estimate = meanOf(values);
  const auto [lowest, highest] = std::minmax_element(values.begin(), values.end());
  if (*lowest == *highest) return {estimate, estimate, estimate};  // every resample has this mean

  const auto means = sortedResampledMeans(values, options.resamples, options.seed);
  const double tail = (1.0 - options.level) / 2.0;
  if (options.method == BootstrapMethod::Percentile)
    return {estimate, sortedQuantile(means, tail), sortedQuantile(means, 1.0 - tail)};

  const double z0 = biasCorrection(means, estimate);
  const double acceleration = jackknifeAcceleration(values);
  const double z_tail = normalQuantile(tail);
  return {estimate, sortedQuantile(means, adjustedTail(z0, acceleration, z_tail)),
          sortedQuantile(means, adjustedTail(z0, acceleration, -z_tail))};
}

}  // namespace occsweep::stats
