// Effect sizes of paired differences (docs/statistics.md).
#pragma once

#include <vector>

namespace occsweep::stats {

struct PairedEffectSize {
  double mean_difference = 0.0;
  double median_difference = 0.0;  ///< mean of the two middle values for an even count
  /// Matched-pairs rank-biserial correlation (Kerby 2014): (W+ - W-) / (W+ + W-) over the non-zero differences,
  /// in [-1, 1]; 0 when every difference is zero.
  double rank_biserial = 0.0;
};

/// Throws std::invalid_argument on an empty sample or a non-finite difference.
[[nodiscard]] PairedEffectSize pairedEffectSize(const std::vector<double>& differences);

}  // namespace occsweep::stats
