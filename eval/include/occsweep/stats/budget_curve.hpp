// Budget curves: the expected best AUC when only n combinations of a grid are tried (docs/statistics.md).
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

namespace occsweep::stats {

/// E[max AUC of n combinations drawn uniformly without replacement from the grid], for n = 1..N (element n-1),
/// by exact order statistics: with a_(1) <= ... <= a_(N), E[max of n] = sum_i a_(i) C(i-1, n-1) / C(N, n).
/// The weights are built by a downward recurrence (all in [0, 1], no factorials), O(N^2) time, O(N) memory.
/// Throws std::invalid_argument on an empty grid or a non-finite AUC.
[[nodiscard]] std::vector<double> expectedBestCurve(std::vector<double> aucs);

/// The smallest n (1-based) whose expected best is strictly greater than `value`; nullopt if none is.
[[nodiscard]] std::optional<std::size_t> firstBudgetAbove(const std::vector<double>& curve, double value);

}  // namespace occsweep::stats
