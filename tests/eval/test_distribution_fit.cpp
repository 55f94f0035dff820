// Section 3.2 fits: each recovers known parameters from samples of its own distribution, reaches a likelihood
// at least as high as the true parameters' (what maximum likelihood means), and its CDF is the integral of its pdf.
#include <catch2/catch.hpp>

#include <cmath>

#include "occsweep/core/splitmix64.hpp"
#include "occsweep/stats/distribution_fit.hpp"

using namespace occsweep;

namespace {

double sumNll(const DistributionFit& f, const std::vector<double>& x) {
  double s = 0.0;
  for (double v : x) s -= std::log(f.pdf(v));
  return s;
}

template <class Draw>
std::vector<double> draw(std::uint64_t seed, std::size_t n, Draw d) {
  SplitMix64 rng(seed);
  std::vector<double> x(n);
  for (auto& v : x) v = d(rng);
  return x;
}

double open01(SplitMix64& rng) { return (double(rng.next() >> 11) + 0.5) * 0x1.0p-53; }

// The fit's own nll equals the sum of -ln pdf, and is no worse than the truth's.
void checkLikelihood(const DistributionFit& fit, const DistributionFit& truth, const std::vector<double>& x) {
  CHECK(fit.nll == Approx(sumNll(fit, x)).epsilon(1e-9));
  CHECK(fit.nll <= sumNll(truth, x) + 1e-6 * std::abs(fit.nll));
}

}  // namespace

TEST_CASE("normal and Rayleigh fits recover known parameters") {
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    SplitMix64 pick(seed * 977);
    const double mu = 0.05 + 0.2 * pick.uniform(), sigma = 0.01 + 0.05 * pick.uniform();
    const auto x = draw(seed, 20000, [&](SplitMix64& r) { return mu + sigma * r.gaussian(); });
    const auto n = fitNormal(x);
    CHECK(n.params[0] == Approx(mu).margin(4 * sigma / std::sqrt(20000.0)));
    CHECK(n.params[1] == Approx(sigma).epsilon(0.03));
    checkLikelihood(n, {Distribution::Normal, {mu, sigma}}, x);

    const double rs = 0.02 + 0.1 * pick.uniform();
    const auto y = draw(seed, 20000, [&](SplitMix64& r) { return rs * std::sqrt(-2 * std::log(open01(r))); });
    const auto ray = fitRayleigh(y);
    CHECK(ray.params[0] == Approx(rs).epsilon(0.02));
    checkLikelihood(ray, {Distribution::Rayleigh, {rs}}, y);
  }
}

TEST_CASE("log-logistic and GEV fits recover known parameters") {
  for (std::uint64_t seed = 1; seed <= 8; ++seed) {
    SplitMix64 pick(seed * 131);
    const double mu = -3.0 + pick.uniform(), s = 0.1 + 0.3 * pick.uniform();
    const auto x = draw(seed, 20000, [&](SplitMix64& r) {
      const double u = open01(r);
      return std::exp(mu + s * std::log(u / (1 - u)));
    });
    const auto ll = fitLogLogistic(x);
    CHECK(ll.params[0] == Approx(mu).margin(0.02));
    CHECK(ll.params[1] == Approx(s).epsilon(0.03));
    checkLikelihood(ll, {Distribution::LogLogistic, {mu, s}}, x);

    const double gm = 0.1 + 0.1 * pick.uniform(), gs = 0.01 + 0.03 * pick.uniform(), xi = -0.3 + 0.6 * pick.uniform();
    const auto y = draw(seed + 100, 20000, [&](SplitMix64& r) {
      const double u = open01(r);
      return std::abs(xi) < 1e-9 ? gm - gs * std::log(-std::log(u)) : gm + gs * (std::pow(-std::log(u), -xi) - 1) / xi;
    });
    const auto g = fitGev(y);
    CAPTURE(seed, gm, gs, xi, g.params[0], g.params[1], g.params[2]);
    CHECK(g.params[0] == Approx(gm).margin(0.03 * gs + 1e-4));
    CHECK(g.params[1] == Approx(gs).epsilon(0.04));
    CHECK(g.params[2] == Approx(xi).margin(0.03));
    checkLikelihood(g, {Distribution::Gev, {gm, gs, xi}}, y);
  }
}

TEST_CASE("CDFs are integrals of their densities, and the KDE follows its samples") {
  const auto x = draw(7, 5000, [](SplitMix64& r) { return 0.1 + 0.02 * r.gaussian(); });
  std::vector<double> pos;
  for (double v : x)
    if (v > 0) pos.push_back(v);
  const auto report = fitDistributions(pos, 100);
  REQUIRE(report.fits.size() == 5);
  for (const auto& f : report.fits) {
    CAPTURE(distributionName(f.kind));
    // d/dx F = f, by central differences at a few points
    for (double at : {0.07, 0.1, 0.13}) {
      const double h = 1e-5;
      CHECK((f.cdf(at + h) - f.cdf(at - h)) / (2 * h) == Approx(f.pdf(at)).epsilon(1e-4).margin(1e-6));
    }
  }
  // A normal sample: normal, log-logistic, GEV and KDE all follow the empirical CDF closely; KS is symmetric.
  const DistributionFit truth{Distribution::Normal, {0.1, 0.02}};
  for (std::size_t a = 0; a < 5; ++a) {
    CHECK(report.ks[a][a] == 0.0);
    for (std::size_t b = 0; b < 5; ++b) CHECK(report.ks[a][b] == report.ks[b][a]);
  }
  CHECK(report.ks_empirical[0] < 0.03);
  CHECK(report.ks_empirical[4] < 0.03);
  double worst = 0.0;
  for (std::size_t i = 0; i < report.grid.size(); ++i)
    worst = std::max(worst, std::abs(report.cdf[4][i] - truth.cdf(report.grid[i])));
  CHECK(worst < 0.03);
  // Rayleigh cannot follow a narrow normal far from zero: the KS distance must show it.
  CHECK(report.ks[2][0] > 0.2);
  // AIC is 2p + 2 nll for the parametric fits.
  CHECK(report.fits[3].aic == Approx(6 + 2 * report.fits[3].nll));
  CHECK(std::isnan(report.fits[4].aic));
}

TEST_CASE("fits refuse samples they cannot use") {
  CHECK_THROWS_AS(fitRayleigh({0.1, -0.2, 0.3}), std::invalid_argument);
  CHECK_THROWS_AS(fitLogLogistic({0.1, 0.0}), std::invalid_argument);
  CHECK_THROWS_AS(fitDistributions({1.0, 2.0, INFINITY}), std::invalid_argument);
}
