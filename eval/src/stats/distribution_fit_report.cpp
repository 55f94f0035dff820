// CDFs and densities of the fits, the kernel density estimate, and Fig. 3's report: CDFs on a common grid, AIC
// and pairwise Kolmogorov-Smirnov distances.
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "occsweep/stats/distribution_fit.hpp"

namespace occsweep {
namespace {

constexpr double kKernelReach = 8.0;  // Gaussian kernels beyond 8 bandwidths contribute < 1e-15

double phi(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }
double gaussian(double z) { return std::exp(-0.5 * z * z) / std::sqrt(2 * M_PI); }

// Sum of fn((x - s_i) / h) over the sorted samples within the kernel's reach of x; `below` counts those under it.
template <class Fn>
double kernelSum(const std::vector<double>& sorted, double h, double x, Fn fn, std::size_t* below) {
  const auto lo = std::lower_bound(sorted.begin(), sorted.end(), x - kKernelReach * h);
  const auto hi = std::upper_bound(sorted.begin(), sorted.end(), x + kKernelReach * h);
  if (below) *below = std::size_t(lo - sorted.begin());
  double sum = 0.0;
  for (auto it = lo; it != hi; ++it) sum += fn((x - *it) / h);
  return sum;
}

double quantile(const std::vector<double>& sorted, double q) {
  const double pos = q * double(sorted.size() - 1);
  const std::size_t i = std::size_t(pos);
  if (i + 1 >= sorted.size()) return sorted.back();
  return sorted[i] + (pos - double(i)) * (sorted[i + 1] - sorted[i]);
}

}  // namespace

double DistributionFit::cdf(double x) const {
  switch (kind) {
    case Distribution::Normal:
      return params[1] > 0 ? phi((x - params[0]) / params[1]) : (x >= params[0] ? 1.0 : 0.0);
    case Distribution::LogLogistic:
      return x <= 0 ? 0.0 : 1.0 / (1.0 + std::exp(-(std::log(x) - params[0]) / params[1]));
    case Distribution::Rayleigh:
      return x <= 0 ? 0.0 : 1.0 - std::exp(-x * x / (2 * params[0] * params[0]));
    case Distribution::Gev: {
      const double z = (x - params[0]) / params[1], xi = params[2];
      if (std::abs(xi) < 1e-9) return std::exp(-std::exp(-z));
      const double t = 1.0 + xi * z;
      if (t <= 0) return xi > 0 ? 0.0 : 1.0;
      return std::exp(-std::pow(t, -1.0 / xi));
    }
    case Distribution::Kde: {
      std::size_t below = 0;
      const double sum = kernelSum(samples, params[0], x, phi, &below);
      return (double(below) + sum) / double(samples.size());
    }
  }
  return std::numeric_limits<double>::quiet_NaN();
}

double DistributionFit::pdf(double x) const {
  switch (kind) {
    case Distribution::Normal: return gaussian((x - params[0]) / params[1]) / params[1];
    case Distribution::LogLogistic: {
      if (x <= 0) return 0.0;
      const double z = (std::log(x) - params[0]) / params[1], e = std::exp(-std::abs(z));
      return e / (params[1] * x * (1 + e) * (1 + e));  // symmetric in z
    }
    case Distribution::Rayleigh: {
      const double s2 = params[0] * params[0];
      return x <= 0 ? 0.0 : x / s2 * std::exp(-x * x / (2 * s2));
    }
    case Distribution::Gev: {
      const double z = (x - params[0]) / params[1], xi = params[2];
      if (std::abs(xi) < 1e-9) return std::exp(-z - std::exp(-z)) / params[1];
      const double t = 1.0 + xi * z;
      if (t <= 0) return 0.0;
      return std::pow(t, -1.0 / xi - 1.0) * std::exp(-std::pow(t, -1.0 / xi)) / params[1];
    }
    case Distribution::Kde:
      return kernelSum(samples, params[0], x, gaussian, nullptr) / (double(samples.size()) * params[0]);
  }
  return std::numeric_limits<double>::quiet_NaN();
}

DistributionFit fitKde(const std::vector<double>& x, std::size_t nll_points) {
  if (x.size() < 2) throw std::invalid_argument("kde fit: needs at least 2 samples");
  DistributionFit f{Distribution::Kde, {}, {"bandwidth"}};
  f.samples = x;
  std::sort(f.samples.begin(), f.samples.end());
  const double median = quantile(f.samples, 0.5);
  std::vector<double> deviations(x.size());
  std::transform(x.begin(), x.end(), deviations.begin(), [&](double v) { return std::abs(v - median); });
  std::sort(deviations.begin(), deviations.end());
  double spread = quantile(deviations, 0.5) / 0.6745;  // MATLAB ksdensity: mad(x, 1) / 0.6745
  if (!(spread > 0)) spread = std::max(f.samples.back() - f.samples.front(), 1e-12) / 4.0;
  f.params = {spread * std::pow(4.0 / (3.0 * double(x.size())), 0.2)};
  // In-sample likelihood (not leave-one-out: optimistic, so the KDE's nll is a floor, not a fair rival).
  const std::size_t stride = std::max<std::size_t>(1, (f.samples.size() + nll_points - 1) / std::max<std::size_t>(nll_points, 1));
  double sum = 0.0;
  std::size_t used = 0;
  for (std::size_t i = 0; i < f.samples.size(); i += stride, ++used) sum -= std::log(f.pdf(f.samples[i]));
  f.nll = sum * double(f.samples.size()) / double(used);
  f.nll_estimated = stride > 1;
  f.aic = std::numeric_limits<double>::quiet_NaN();
  return f;
}

DistributionReport fitDistributions(const std::vector<double>& s, std::size_t grid_points) {
  DistributionReport r;
  std::vector<double> x;
  x.reserve(s.size());
  for (double v : s)
    if (std::isfinite(v) && v > 0) x.push_back(v);
  r.samples = x.size();
  r.dropped = s.size() - x.size();
  if (x.size() < 10) throw std::invalid_argument("distribution fits: fewer than 10 finite positive samples");
  r.fits = {fitNormal(x), fitLogLogistic(x), fitRayleigh(x), fitGev(x), fitKde(x)};
  const std::vector<double>& sorted = r.fits.back().samples;
  const double lo = sorted.front(), hi = quantile(sorted, 0.999);
  grid_points = std::max<std::size_t>(grid_points, 2);
  for (std::size_t i = 0; i < grid_points; ++i) r.grid.push_back(lo + (hi - lo) * double(i) / double(grid_points - 1));
  for (double g : r.grid)
    r.empirical_cdf.push_back(double(std::upper_bound(sorted.begin(), sorted.end(), g) - sorted.begin()) /
                              double(sorted.size()));
  for (const auto& f : r.fits) {
    r.cdf.emplace_back();
    for (double g : r.grid) r.cdf.back().push_back(f.cdf(g));
  }
  auto distance = [&](const std::vector<double>& a, const std::vector<double>& b) {
    double d = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) d = std::max(d, std::abs(a[i] - b[i]));
    return d;
  };
  r.ks.assign(r.fits.size(), std::vector<double>(r.fits.size(), 0.0));
  for (std::size_t a = 0; a < r.fits.size(); ++a) {
    for (std::size_t b = 0; b < r.fits.size(); ++b) r.ks[a][b] = distance(r.cdf[a], r.cdf[b]);
    r.ks_empirical.push_back(distance(r.cdf[a], r.empirical_cdf));
  }
  return r;
}

}  // namespace occsweep
