// Leave-one-group-out selection (docs/statistics.md) against a brute-force loop and a hand case with ties.
#include <stdexcept>
#include <vector>

#include <catch2/catch.hpp>

#include "occsweep/core/splitmix64.hpp"
#include "occsweep/stats/cross_validation.hpp"

using occsweep::SplitMix64;
using occsweep::stats::leaveOneGroupOut;

TEST_CASE("Hand case: ties go to the lowest combination id, for the optimum and for the choice", "[stats]") {
  const std::vector<std::vector<double>> auc{{0.5, 0.9, 0.9}, {0.7, 0.6, 0.6}, {0.8, 0.8, 0.4}};
  const auto cv = leaveOneGroupOut(auc);
  REQUIRE(cv.groups.size() == 3);
  // Group 0 held out: other sums 1.5, 1.4, 1.0 -> combination 0; its own best 0.9 ties 1 and 2 -> 1.
  CHECK(cv.groups[0].chosen_combination == 0);
  CHECK(cv.groups[0].cv_score == 0.5);
  CHECK(cv.groups[0].optimum_combination == 1);
  CHECK(cv.groups[0].gap == Approx(0.4).epsilon(1e-15));
  // Group 1 held out: sums 1.3, 1.7, 1.3 -> 1.
  CHECK(cv.groups[1].chosen_combination == 1);
  CHECK(cv.groups[1].cv_score == 0.6);
  CHECK(cv.groups[1].optimum_combination == 0);
  // Group 2 held out: sums 1.2, 1.5, 1.5 tie -> 1; its own best 0.8 ties 0 and 1 -> 0; gap 0.
  CHECK(cv.groups[2].chosen_combination == 1);
  CHECK(cv.groups[2].optimum_combination == 0);
  CHECK(cv.groups[2].gap == 0.0);
  CHECK(cv.mean_gap == Approx((0.4 + 0.1 + 0.0) / 3.0).epsilon(1e-14));
  CHECK(cv.mean_optimum == Approx((0.9 + 0.7 + 0.8) / 3.0).epsilon(1e-14));
  CHECK(cv.mean_cv_score == Approx((0.5 + 0.6 + 0.8) / 3.0).epsilon(1e-14));
}

TEST_CASE("Leave-one-group-out agrees with a brute-force loop on random tables with ties", "[stats]") {
  SplitMix64 rng(13);
  for (int seed = 0; seed < 300; ++seed) {
    const std::size_t groups = 2 + rng.below(7), combinations = 1 + rng.below(20);
    // Multiples of 1/64: every sum is exact, so the oracle's means tie exactly where the sums do.
    std::vector<std::vector<double>> auc(groups, std::vector<double>(combinations));
    for (auto& row : auc)
      for (double& value : row) value = double(48 + rng.below(17)) / 64.0;
    const auto cv = leaveOneGroupOut(auc);
    for (std::size_t held = 0; held < groups; ++held) {
      std::size_t chosen = 0, optimum = 0;
      double best_mean = -1.0;
      for (std::size_t c = 0; c < combinations; ++c) {
        double sum = 0.0;
        for (std::size_t g = 0; g < groups; ++g)
          if (g != held) sum += auc[g][c];
        const double mean = sum / double(groups - 1);  // one rounding, monotone in the exact sum
        if (mean > best_mean) best_mean = mean, chosen = c;
        if (auc[held][c] > auc[held][optimum]) optimum = c;
      }
      INFO("table " << seed << ", held-out group " << held);
      REQUIRE(cv.groups[held].chosen_combination == chosen);
      REQUIRE(cv.groups[held].optimum_combination == optimum);
      REQUIRE(cv.groups[held].cv_score == auc[held][chosen]);
      REQUIRE(cv.groups[held].gap == auc[held][optimum] - auc[held][chosen]);
      REQUIRE(cv.groups[held].gap >= 0.0);
    }
  }
}

TEST_CASE("Leave-one-group-out refuses fewer than 2 groups, ragged rows, no combination, non-finite AUCs",
          "[stats]") {
  CHECK_THROWS_WITH(leaveOneGroupOut({{0.5, 0.6}}), Catch::Contains("at least 2 groups"));
  CHECK_THROWS_WITH(leaveOneGroupOut({{0.5, 0.6}, {0.5}}), Catch::Contains("group 1 has 1 combinations"));
  CHECK_THROWS_WITH(leaveOneGroupOut({{}, {}}), Catch::Contains("at least 1 combination"));
  CHECK_THROWS_WITH(leaveOneGroupOut({{0.5}, {NAN}}), Catch::Contains("not finite"));
}

TEST_CASE("Leave one set out picks a sibling-tuned optimum, leave one data set out does not", "[stats]") {
  // Three data sets of two point cloud sets each (A1 A2 B1 B2 C1 C2). Combination 0 is generic (0.70 on every set);
  // combination 1 is tuned to data set A's scene (0.90 on A's sets, 0.66 elsewhere).
  const std::vector<std::vector<double>> sets{{0.70, 0.90}, {0.70, 0.90}, {0.70, 0.66},
                                              {0.70, 0.66}, {0.70, 0.66}, {0.70, 0.66}};
  const auto by_set = leaveOneGroupOut(sets);
  // A1 held out: A2 is still in the choice, and tips it to the tuned combination ((0.90 + 4 x 0.66) / 5 = 0.708).
  CHECK(by_set.groups[0].chosen_combination == 1);
  CHECK(by_set.groups[0].cv_score == 0.90);
  CHECK(by_set.groups[0].gap == 0.0);  // the held-out score is the set's own optimum: no honest hold-out
  // The data sets, each the mean of its sets: A held out, B and C choose the generic combination.
  const std::vector<std::vector<double>> datasets{{0.70, 0.90}, {0.70, 0.66}, {0.70, 0.66}};
  const auto by_dataset = leaveOneGroupOut(datasets);
  CHECK(by_dataset.groups[0].chosen_combination == 0);
  CHECK(by_dataset.groups[0].cv_score == 0.70);
  CHECK(by_dataset.groups[0].gap == Approx(0.20).epsilon(1e-12));
}
