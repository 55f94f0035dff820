// Holm's step-down correction of a family of p-values (docs/statistics.md, "Verdicts").
#pragma once

#include <vector>

namespace occsweep::stats {

/// Holm-adjusted p-values, in input order: with the p-values sorted, p_(1) <= ... <= p_(m),
/// adjusted_(i) = max_{j <= i} min(1, (m - j + 1) p_(j)) (Holm, Scand. J. Statistics 6, 1979). Rejecting where the
/// adjusted value is at most alpha keeps the family-wise error rate at alpha. Equal p-values get equal adjusted
/// values. Throws std::invalid_argument naming the index of a p-value that is NaN or outside [0, 1].
[[nodiscard]] std::vector<double> holmAdjusted(const std::vector<double>& p_values);

}  // namespace occsweep::stats
