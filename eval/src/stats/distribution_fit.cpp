// Maximum-likelihood fits of Section 3.2: closed forms where they exist, Nelder-Mead elsewhere.
#include "occsweep/stats/distribution_fit.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numeric>
#include <stdexcept>

namespace occsweep {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

double mean(const std::vector<double>& x) { return std::accumulate(x.begin(), x.end(), 0.0) / double(x.size()); }

double deviation(const std::vector<double>& x, double m) {
  double q = 0.0;
  for (double v : x) q += (v - m) * (v - m);
  return std::sqrt(q / double(x.size()));
}

void needSamples(const std::vector<double>& x, bool positive, const char* what) {
  if (x.size() < 2) throw std::invalid_argument(std::string(what) + " fit: needs at least 2 samples");
  for (double v : x)
    if (!std::isfinite(v) || (positive && !(v > 0)))
      throw std::invalid_argument(std::string(what) + " fit: samples must be finite" + (positive ? " and > 0" : ""));
}

// Nelder-Mead simplex minimiser (Lagarias et al. 1998 coefficients); +inf values are simply worst.
std::vector<double> nelderMead(const std::function<double(const std::vector<double>&)>& f, std::vector<double> start,
                               const std::vector<double>& step, int max_evaluations = 4000) {
  const std::size_t n = start.size();
  std::vector<std::vector<double>> simplex(n + 1, start);
  for (std::size_t i = 0; i < n; ++i) simplex[i + 1][i] += step[i];
  std::vector<double> value(n + 1);
  for (std::size_t i = 0; i <= n; ++i) value[i] = f(simplex[i]);
  int evaluations = int(n + 1);
  std::vector<std::size_t> order(n + 1);
  while (evaluations < max_evaluations) {
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return value[a] < value[b]; });
    const std::size_t best = order[0], worst = order[n], second = order[n - 1];
    double spread = 0.0;
    for (std::size_t i = 0; i <= n; ++i)
      for (std::size_t d = 0; d < n; ++d) spread = std::max(spread, std::abs(simplex[i][d] - simplex[best][d]));
    if (spread < 1e-10 && std::abs(value[worst] - value[best]) <= 1e-12 * (1 + std::abs(value[best]))) break;
    std::vector<double> centroid(n, 0.0);
    for (std::size_t i = 0; i <= n; ++i)
      if (i != worst)
        for (std::size_t d = 0; d < n; ++d) centroid[d] += simplex[i][d] / double(n);
    auto along = [&](double t) {
      std::vector<double> p(n);
      for (std::size_t d = 0; d < n; ++d) p[d] = centroid[d] + t * (simplex[worst][d] - centroid[d]);
      return p;
    };
    const auto reflected = along(-1.0);
    const double fr = f(reflected);
    ++evaluations;
    if (fr < value[best]) {
      const auto expanded = along(-2.0);
      const double fe = f(expanded);
      ++evaluations;
      if (fe < fr) simplex[worst] = expanded, value[worst] = fe;
      else simplex[worst] = reflected, value[worst] = fr;
      continue;
    }
    if (fr < value[second]) {
      simplex[worst] = reflected, value[worst] = fr;
      continue;
    }
    const auto contracted = fr < value[worst] ? along(-0.5) : along(0.5);
    const double fc = f(contracted);
    ++evaluations;
    if (fc < std::min(fr, value[worst])) {
      simplex[worst] = contracted, value[worst] = fc;
      continue;
    }
    for (std::size_t i = 0; i <= n; ++i) {  // shrink towards the best
      if (i == best) continue;
      for (std::size_t d = 0; d < n; ++d) simplex[i][d] = simplex[best][d] + 0.5 * (simplex[i][d] - simplex[best][d]);
      value[i] = f(simplex[i]);
      ++evaluations;
    }
  }
  const auto it = std::min_element(value.begin(), value.end());
  return simplex[std::size_t(it - value.begin())];
}

double logLogisticNll(const std::vector<double>& x, double mu, double s) {
  if (!(s > 0)) return kInf;
  double nll = 0.0;
  for (double v : x) {
    const double z = (std::log(v) - mu) / s;
    // -ln f(x) = ln s + ln x - z + 2 ln(1 + e^z), with ln(1 + e^z) evaluated without overflow
    nll += std::log(s) + std::log(v) - z + 2.0 * (z > 0 ? z + std::log1p(std::exp(-z)) : std::log1p(std::exp(z)));
  }
  return nll;
}

double gevNll(const std::vector<double>& x, double mu, double sigma, double xi) {
  if (!(sigma > 0)) return kInf;
  double nll = double(x.size()) * std::log(sigma);
  const bool gumbel = std::abs(xi) < 1e-9;
  for (double v : x) {
    const double z = (v - mu) / sigma;
    if (gumbel) {
      nll += z + std::exp(-z);
      continue;
    }
    const double t = 1.0 + xi * z;
    if (!(t > 0)) return kInf;  // outside the support
    nll += (1.0 + 1.0 / xi) * std::log(t) + std::pow(t, -1.0 / xi);
  }
  return nll;
}

}  // namespace

const char* distributionName(Distribution d) {
  switch (d) {
    case Distribution::Normal: return "normal";
    case Distribution::LogLogistic: return "log-logistic";
    case Distribution::Rayleigh: return "rayleigh";
    case Distribution::Gev: return "gev";
    case Distribution::Kde: return "kde";
  }
  return "?";
}

DistributionFit fitNormal(const std::vector<double>& x) {
  needSamples(x, false, "normal");
  const double m = mean(x), sd = deviation(x, m);
  DistributionFit f{Distribution::Normal, {m, sd}, {"mu", "sigma"}};
  const double n = double(x.size());
  f.nll = sd > 0 ? n * (0.5 * std::log(2 * M_PI) + std::log(sd) + 0.5) : -kInf;
  f.aic = 2 * 2 + 2 * f.nll;
  return f;
}

DistributionFit fitRayleigh(const std::vector<double>& x) {
  needSamples(x, true, "rayleigh");
  double squares = 0.0, logs = 0.0;
  for (double v : x) squares += v * v, logs += std::log(v);
  const double n = double(x.size()), var = squares / (2 * n);
  DistributionFit f{Distribution::Rayleigh, {std::sqrt(var)}, {"sigma"}};
  f.nll = n * std::log(var) - logs + squares / (2 * var);  // -ln f = ln sigma^2 - ln x + x^2 / (2 sigma^2)
  f.aic = 2 * 1 + 2 * f.nll;
  return f;
}

DistributionFit fitLogLogistic(const std::vector<double>& x) {
  needSamples(x, true, "log-logistic");
  std::vector<double> y(x.size());
  std::transform(x.begin(), x.end(), y.begin(), [](double v) { return std::log(v); });
  const double m = mean(y), s0 = std::max(deviation(y, m) * std::sqrt(3.0) / M_PI, 1e-12);
  const auto p = nelderMead([&](const std::vector<double>& q) { return logLogisticNll(x, q[0], std::exp(q[1])); },
                            {m, std::log(s0)}, {0.1 * s0 + 1e-12, 0.2});
  DistributionFit f{Distribution::LogLogistic, {p[0], std::exp(p[1])}, {"mu", "s"}};
  f.nll = logLogisticNll(x, p[0], std::exp(p[1]));
  f.aic = 2 * 2 + 2 * f.nll;
  return f;
}

DistributionFit fitGev(const std::vector<double>& x) {
  needSamples(x, false, "gev");
  const double m = mean(x), sd = std::max(deviation(x, m), 1e-12);
  const double sigma0 = sd * std::sqrt(6.0) / M_PI, mu0 = m - 0.5772156649 * sigma0;  // Gumbel moments
  auto nll = [&](const std::vector<double>& q) { return gevNll(x, q[0], std::exp(q[1]), q[2]); };
  std::vector<double> best;
  double best_nll = kInf;
  for (double xi0 : {-0.2, 0.0, 0.2}) {
    // A start outside the support for some sample has nll +inf: widen sigma until every sample is inside.
    double log_sigma = std::log(sigma0);
    for (int i = 0; i < 60 && !std::isfinite(nll({mu0, log_sigma, xi0})); ++i) log_sigma += 0.25;
    if (!std::isfinite(nll({mu0, log_sigma, xi0}))) continue;
    const auto p = nelderMead(nll, {mu0, log_sigma, xi0}, {0.2 * sigma0, 0.2, 0.05});
    const double v = nll(p);
    if (v < best_nll) best_nll = v, best = p;
  }
  if (best.empty()) throw std::invalid_argument("gev fit: no start inside the support");
  DistributionFit f{Distribution::Gev, {best[0], std::exp(best[1]), best[2]}, {"mu", "sigma", "xi"}};
  f.nll = best_nll;
  f.aic = 2 * 3 + 2 * f.nll;
  return f;
}

}  // namespace occsweep
