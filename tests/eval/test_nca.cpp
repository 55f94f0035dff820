// NCA for regression: the gradient matches finite differences, and on synthetic data where only known features
// matter those features get the large weights, over many seeds.
#include <catch2/catch.hpp>

#include <cmath>

#include "occsweep/core/splitmix64.hpp"
#include "occsweep/stats/nca.hpp"

using namespace occsweep;

namespace {

struct Synthetic {
  Eigen::MatrixXd x;
  Eigen::VectorXd y;
};

// Five features: 0 and 1 drive y (0 more strongly), 2 and 3 are noise, 4 is a k-like discrete noise feature.
Synthetic makeData(std::uint64_t seed, int n) {
  SplitMix64 rng(seed);
  Synthetic s{Eigen::MatrixXd(n, 5), Eigen::VectorXd(n)};
  for (int i = 0; i < n; ++i) {
    for (int r = 0; r < 4; ++r) s.x(i, r) = rng.uniform();
    s.x(i, 4) = double(1 + 2 * rng.below(4));
    s.y(i) = std::sin(3.0 * s.x(i, 0)) + 0.4 * s.x(i, 1) + 0.02 * rng.gaussian();
  }
  return s;
}

}  // namespace

TEST_CASE("NCA objective gradient matches central differences") {
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    const Synthetic s = makeData(seed, 40);
    SplitMix64 rng(seed + 50);
    Eigen::VectorXd w(5);
    for (int r = 0; r < 5; ++r) w(r) = 0.2 + rng.uniform();
    const double lambda = 0.03, sigma = 0.7;
    Eigen::VectorXd g;
    const double f = ncaObjective(s.x, s.y, w, lambda, sigma, &g);
    CHECK(f == Approx(ncaObjective(s.x, s.y, w, lambda, sigma, nullptr)));
    for (int r = 0; r < 5; ++r) {
      const double h = 1e-6;
      Eigen::VectorXd up = w, down = w;
      up(r) += h, down(r) -= h;
      const double numeric = (ncaObjective(s.x, s.y, up, lambda, sigma, nullptr) -
                              ncaObjective(s.x, s.y, down, lambda, sigma, nullptr)) / (2 * h);
      CHECK(g(r) == Approx(numeric).epsilon(1e-5).margin(1e-8));
    }
  }
}

TEST_CASE("NCA ranks the relevant features above the irrelevant ones") {
  NcaConfig c;
  c.folds = 3;
  c.lambda_factors = {0.25, 1.0, 4.0};
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    const Synthetic s = makeData(seed, 200);
    const NcaResult r = ncaFeatureWeights(s.x, s.y, c);
    CAPTURE(seed, r.normalized[0], r.normalized[1], r.normalized[2], r.normalized[3], r.normalized[4], r.lambda);
    REQUIRE(r.normalized.size() == 5);
    double sum = 0.0;
    for (double v : r.normalized) sum += v;
    CHECK(sum == Approx(1.0));
    CHECK(r.normalized[0] > r.normalized[1]);
    for (int noise = 2; noise < 5; ++noise) {
      CHECK(r.normalized[1] > 2 * r.normalized[noise]);
      CHECK(r.normalized[noise] < 0.1);  // what the paper asks of k: an irrelevant feature falls below 0.1
    }
    CHECK(r.cv_loss.size() == 3);
  }
}

TEST_CASE("fitted weights lower the objective, and bad input is refused") {
  const Synthetic s = makeData(9, 80);
  NcaConfig c;
  Eigen::MatrixXd standardized = s.x;
  for (int r = 0; r < 5; ++r) {
    const double m = standardized.col(r).mean();
    const double sd = std::sqrt((standardized.col(r).array() - m).square().mean());
    standardized.col(r) = (standardized.col(r).array() - m) / sd;
  }
  int iterations = 0;
  const double lambda = 1.0 / 80;
  const Eigen::VectorXd w = fitNcaWeights(standardized, s.y, lambda, c, &iterations);
  CHECK(iterations > 0);
  CHECK(ncaObjective(standardized, s.y, w, lambda, c.sigma, nullptr) <
        ncaObjective(standardized, s.y, Eigen::VectorXd::Ones(5), lambda, c.sigma, nullptr));
  CHECK_THROWS_AS(ncaFeatureWeights(Eigen::MatrixXd(2, 3), Eigen::VectorXd(2)), std::invalid_argument);
  Eigen::MatrixXd bad = s.x;
  bad(3, 1) = NAN;
  CHECK_THROWS_AS(ncaFeatureWeights(bad, s.y), std::invalid_argument);
}
