// Section 3.2 / Fig. 3: the average distances s_i of a point cloud set fitted by maximum likelihood with the
// normal, log-logistic, Rayleigh and generalised extreme value (GEV) distributions, and a Gaussian kernel density
// estimate (KDE); each CDF on a common grid, negative log-likelihood, AIC and pairwise Kolmogorov-Smirnov distances.
#pragma once

#include <string>
#include <vector>

namespace occsweep {

enum class Distribution { Normal, LogLogistic, Rayleigh, Gev, Kde };

[[nodiscard]] const char* distributionName(Distribution d);

/// One fitted distribution. Parameters by kind (names in `param_names`):
/// Normal {mu, sigma}; LogLogistic {mu, s}: ln x is logistic(mu, s), MATLAB's parameterisation;
/// Rayleigh {sigma}; Gev {mu, sigma, xi} (xi = 0 is Gumbel); Kde {bandwidth}.
struct DistributionFit {
  Distribution kind = Distribution::Normal;
  std::vector<double> params;
  std::vector<std::string> param_names{};
  double nll = 0.0;   ///< negative log-likelihood of the samples under the fit
  double aic = 0.0;   ///< 2 * parameters + 2 * nll; NaN for the KDE, which has no fixed parameter count
  bool nll_estimated = false;  ///< KDE: nll extrapolated from a stride subsample (see fitKde)
  std::vector<double> samples{};  ///< KDE only: the sorted samples its CDF sums over

  [[nodiscard]] double cdf(double x) const;
  [[nodiscard]] double pdf(double x) const;
};

/// Closed-form maximum likelihood: sample mean and sqrt(Q/n).
[[nodiscard]] DistributionFit fitNormal(const std::vector<double>& x);
/// Closed form: sigma^2 = sum x^2 / (2n).
[[nodiscard]] DistributionFit fitRayleigh(const std::vector<double>& x);
/// Nelder-Mead on (mu, ln s) of the logistic of ln x, from the moment estimates. Needs x > 0.
[[nodiscard]] DistributionFit fitLogLogistic(const std::vector<double>& x);
/// Nelder-Mead on (mu, ln sigma, xi) from Gumbel moment estimates, best of starts xi in {-0.2, 0, 0.2}.
[[nodiscard]] DistributionFit fitGev(const std::vector<double>& x);
/// Gaussian kernels with MATLAB ksdensity's normal-reference bandwidth: MAD / 0.6745 * (4 / (3n))^(1/5).
/// nll from at most `nll_points` samples taken at a stride, scaled to n (exact when n <= nll_points).
[[nodiscard]] DistributionFit fitKde(const std::vector<double>& x, std::size_t nll_points = 4000);

/// Everything Fig. 3 needs for one set of samples.
struct DistributionReport {
  std::size_t samples = 0;            ///< finite, positive s_i used
  std::size_t dropped = 0;            ///< infinite or non-positive s_i left out (no neighbour within s_c)
  std::vector<double> grid;           ///< common x grid: min sample to the 0.999 quantile
  std::vector<double> empirical_cdf;  ///< on the grid
  std::vector<DistributionFit> fits;  ///< normal, log-logistic, Rayleigh, GEV, KDE
  std::vector<std::vector<double>> cdf;  ///< per fit, on the grid
  std::vector<std::vector<double>> ks;   ///< ks[a][b]: max over the grid of |F_a - F_b|
  std::vector<double> ks_empirical;      ///< per fit: max over the grid of |F - empirical|
};

/// Fits all five to the finite positive samples; throws std::invalid_argument with fewer than 10 of them.
[[nodiscard]] DistributionReport fitDistributions(const std::vector<double>& s, std::size_t grid_points = 200);

}  // namespace occsweep
