// Eq. 17 and Eq. 18 fits recover known coefficients from noisy samples.
#include <catch2/catch.hpp>

#include "occsweep/core/splitmix64.hpp"
#include "occsweep/stats/runtime_model.hpp"

using namespace occsweep;

TEST_CASE("Eq. 17 and Eq. 18 fits recover known coefficients") {
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    SplitMix64 rng(seed);
    const double a = 2.3371e-5 * (0.5 + rng.uniform()), b = 0.69527 * (0.5 + rng.uniform());
    std::vector<RuntimeSample> om;
    for (int i = 0; i < 40; ++i) {
      const double n = 1e4 + rng.uniform() * 1e6;
      om.push_back({n, 0, a * n + b + rng.gaussian() * 1e-3});
    }
    const RuntimeFit f17 = fitEq17(om);
    CHECK(f17.a == Approx(a).epsilon(1e-3));
    CHECK(f17.b == Approx(b).epsilon(1e-2));
    CHECK(f17.r_squared > 0.999);
    const double a18 = 7.3592e-7 * (0.5 + rng.uniform()), b18 = 2.7681e-5, c18 = 1.5148;
    std::vector<RuntimeSample> knn;
    for (int i = 0; i < 60; ++i) {
      const double n = 1e4 + rng.uniform() * 1e6, k = double(1 + 2 * rng.below(4));
      knn.push_back({n, k, (a18 * k + b18) * n + c18 + rng.gaussian() * 1e-3});
    }
    const RuntimeFit f18 = fitEq18(knn);
    CHECK(f18.a == Approx(a18).epsilon(1e-2));
    CHECK(f18.b == Approx(b18).epsilon(1e-2));
    CHECK(f18.c == Approx(c18).epsilon(1e-2));
  }
  CHECK_THROWS_AS(fitEq17({{1, 0, 1}, {1, 0, 2}}), std::invalid_argument);  // one distinct N: undetermined
}
