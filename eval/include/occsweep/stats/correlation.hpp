// Correlation of paired values: Pearson r, Spearman rho, a permutation test and the values within groups
// (docs/statistics.md, "Correlation").
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace occsweep::stats {

enum class CorrelationKind {
  Pearson,   ///< Pearson's r of the values
  Spearman,  ///< Spearman's rho: Pearson's r of the mid-ranks
};

/// Pearson's r of paired values, in [-1, 1]; NaN when x or y is constant (SciPy's convention).
/// Throws std::invalid_argument on fewer than 2 pairs, unequal lengths or a non-finite value.
[[nodiscard]] double pearsonCorrelation(const std::vector<double>& x, const std::vector<double>& y);

/// Spearman's rho: Pearson's r of the mid-ranks (midRanks in wilcoxon.hpp). Same conventions as pearsonCorrelation.
[[nodiscard]] double spearmanCorrelation(const std::vector<double>& x, const std::vector<double>& y);

/// The correlation of `kind` (pearsonCorrelation or spearmanCorrelation).
[[nodiscard]] double correlation(const std::vector<double>& x, const std::vector<double>& y, CorrelationKind kind);

struct PermutationOptions {
  CorrelationKind kind = CorrelationKind::Pearson;
  std::size_t resamples = 10000;  ///< Monte Carlo permutations when n > kMaxExactPermutationCount
  std::uint64_t seed = 1;         ///< SplitMix64 seed: the same values and seed give the same p-value
};

/// Up to this many pairs the permutation test enumerates all n! permutations (8! = 40,320).
inline constexpr std::size_t kMaxExactPermutationCount = 8;

struct PermutationResult {
  double statistic = 0.0;      ///< the observed correlation (signed)
  double p_value = 1.0;        ///< two-sided: share of permutations with |r| at least the observed |r|
  std::size_t permutations = 0;  ///< n! when exact, else the number of random permutations
  bool exact = false;
};

/// Two-sided permutation test of "x and y are unrelated": the correlation of x with permuted y, statistic |r|.
/// Exact (every permutation, p = count / n!) for n <= kMaxExactPermutationCount, otherwise seeded Monte Carlo with
/// p = (count + 1) / (resamples + 1), as SciPy's permutation_test. Throws std::invalid_argument on the inputs
/// pearsonCorrelation refuses, on a constant x or y (no correlation is defined) and on zero resamples.
[[nodiscard]] PermutationResult correlationPermutationTest(const std::vector<double>& x, const std::vector<double>& y,
                                                           const PermutationOptions& options = {});

struct GroupCorrelation {
  std::string group;
  std::size_t n = 0;
  double pearson = 0.0;   ///< NaN when the group has fewer than 2 pairs or a constant x or y
  double spearman = 0.0;
};

/// Pearson's r and Spearman's rho within each group (group[i] labels pair i), groups in sorted label order.
/// Throws std::invalid_argument on unequal lengths or a non-finite value.
[[nodiscard]] std::vector<GroupCorrelation> correlationWithinGroups(const std::vector<double>& x,
                                                                    const std::vector<double>& y,
                                                                    const std::vector<std::string>& group);

/// The pooled within-group Pearson r: r of x and y after subtracting each group's means, so that differences
/// between the groups' means (a between-group trend, Simpson's paradox) do not count. NaN when nothing varies
/// within the groups. Throws as correlationWithinGroups.
[[nodiscard]] double pooledWithinGroupPearson(const std::vector<double>& x, const std::vector<double>& y,
                                              const std::vector<std::string>& group);

}  // namespace occsweep::stats
