// Paired Wilcoxon signed-rank test, two-sided (docs/statistics.md).
#pragma once

#include <cstddef>
#include <vector>

namespace occsweep::stats {

enum class SignedRankMode {
  Auto,    ///< Exact when at most 50 non-zero differences and no tied |difference|, else Approx
  Exact,   ///< exact null distribution (no ties allowed: throws std::invalid_argument on ties)
  Approx,  ///< normal approximation with the tie correction of the variance
};

/// Exact mode's largest sample: its null distribution takes n(n+1)/2 + 1 doubles and O(n^3) time.
inline constexpr std::size_t kMaxExactSignedRankCount = 1000;

struct SignedRankOptions {
  SignedRankMode mode = SignedRankMode::Auto;
  bool continuity_correction = true;  ///< in Approx mode only
};

struct SignedRankResult {
  double w_plus = 0.0;     ///< sum of the ranks of positive differences (mid-ranks on ties)
  double w_minus = 0.0;
  double statistic = 0.0;  ///< min(w_plus, w_minus), as SciPy reports it for the two-sided test
  double p_value = 1.0;
  double z = 0.0;          ///< the normal score in Approx mode, 0 in Exact mode
  std::size_t used = 0;    ///< non-zero differences (zeros are dropped, SciPy's zero_method="wilcox")
  bool exact = false;
};

/// The two-sided test of "the differences are symmetric about 0". Zero differences are dropped before ranking.
/// Throws std::invalid_argument on a non-finite difference or when every difference is zero.
[[nodiscard]] SignedRankResult wilcoxonSignedRank(const std::vector<double>& differences,
                                                  const SignedRankOptions& options = {});

/// Mid-ranks (1-based, ties share their mean rank) of values, in input order.
[[nodiscard]] std::vector<double> midRanks(const std::vector<double>& values);

}  // namespace occsweep::stats
