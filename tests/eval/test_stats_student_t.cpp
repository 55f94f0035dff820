// Student's t against SciPy's t.cdf and t.ppf (tools/verdict_reference.py), its closed forms (1 and 2 degrees of
// freedom), the normal limit and a published table of critical values; the t interval against a hand computation.
#include <cmath>
#include <vector>

#include <catch2/catch.hpp>

#include "occsweep/core/splitmix64.hpp"
#include "occsweep/stats/student_t.hpp"
#include "verdict_reference_cases.hpp"

using namespace occsweep::stats;

TEST_CASE("Student's t CDF equals its closed forms for 1 and 2 degrees of freedom", "[stats]") {
  occsweep::SplitMix64 rng(7);
  for (int i = 0; i < 2000; ++i) {
    const double t = (rng.uniform() - 0.5) * 200.0 * rng.uniform();
    INFO("t = " << t);
    CHECK(studentTCdf(t, 1) == Approx(0.5 + std::atan(t) / M_PI).margin(1e-13));  // Cauchy
    CHECK(studentTCdf(t, 2) == Approx(0.5 + t / (2.0 * std::sqrt(2.0 + t * t))).margin(1e-13));
  }
}

TEST_CASE("Student's t CDF and quantile equal SciPy's t.cdf and t.ppf, df from 0.5 to 119", "[stats]") {
  for (const auto& r : occsweep::test::kStudentTCdf) {
    INFO("df = " << r.df << ", t = " << r.x);
    CHECK(studentTCdf(r.x, r.df) == Approx(r.value).epsilon(1e-11).margin(1e-15));
  }
  // SciPy's t.ppf (cephes' stdtrit) is itself good to about 1e-9: at df = 2, p = 0.9875 it gives 6.2053468234, whose
  // CDF by the closed form is 0.98750000002649, where ours gives 6.2053468166 with a CDF of 0.9875 to the last bit.
  for (const auto& r : occsweep::test::kStudentTQuantile) {
    INFO("df = " << r.df << ", p = " << r.x);
    CHECK(studentTQuantile(r.x, r.df) == Approx(r.value).epsilon(1e-8).margin(1e-12));
  }
}

TEST_CASE("Student's t tends to the normal distribution", "[stats]") {
  for (double t : {-3.0, -1.0, 0.0, 0.5, 2.0})
    CHECK(studentTCdf(t, 1e7) == Approx(0.5 * std::erfc(-t / std::sqrt(2.0))).margin(1e-6));
}

TEST_CASE("Student's t quantiles match a published table of critical values", "[stats]") {
  // Two-sided 90 % and 95 % critical values, e.g. NIST/SEMATECH e-Handbook of Statistical Methods, table 1.3.6.7.2.
  struct Row { double df, t95, t975; };
  for (const Row r : {Row{1, 6.314, 12.706}, Row{2, 2.920, 4.303}, Row{5, 2.015, 2.571}, Row{7, 1.895, 2.365},
                      Row{10, 1.812, 2.228}, Row{19, 1.729, 2.093}, Row{30, 1.697, 2.042}, Row{100, 1.660, 1.984}}) {
    INFO("df = " << r.df);
    CHECK(studentTQuantile(0.95, r.df) == Approx(r.t95).margin(5e-4));
    CHECK(studentTQuantile(0.975, r.df) == Approx(r.t975).margin(5e-4));
    CHECK(studentTQuantile(0.05, r.df) == -studentTQuantile(0.95, r.df));
  }
}

TEST_CASE("Student's t quantile inverts the CDF over many p and df", "[stats]") {
  occsweep::SplitMix64 rng(11);
  for (int i = 0; i < 500; ++i) {
    const double p = 0.001 + 0.998 * rng.uniform(), df = 0.5 + 60.0 * rng.uniform();
    INFO("p = " << p << ", df = " << df);
    CHECK(studentTCdf(studentTQuantile(p, df), df) == Approx(p).margin(1e-12));
  }
  CHECK_THROWS(studentTQuantile(0.0, 3));
  CHECK_THROWS(studentTQuantile(1.0, 3));
  CHECK_THROWS(studentTCdf(1.0, 0.0));
  CHECK_THROWS(studentTCdf(std::nan(""), 3.0));
}

TEST_CASE("The t interval of a mean, by hand", "[stats]") {
  // 1, 2, 3, 4: mean 2.5, s = sqrt(5/3), s / sqrt(4) = 0.645497; t_{0.95, 3} = 2.353363.
  const MeanTInterval t = meanTInterval({1, 2, 3, 4}, 0.9);
  CHECK(t.mean == 2.5);
  CHECK(t.lower == Approx(2.5 - 2.353363 * 0.645497).margin(1e-5));
  CHECK(t.upper == Approx(2.5 + 2.353363 * 0.645497).margin(1e-5));
  CHECK(t.n == 4);
  const MeanTInterval equal = meanTInterval({0.3, 0.3, 0.3}, 0.9);
  CHECK(equal.lower == 0.3);
  CHECK(equal.upper == 0.3);
  CHECK_THROWS_WITH(meanTInterval({1.0}, 0.9), Catch::Contains("at least 2"));
}
