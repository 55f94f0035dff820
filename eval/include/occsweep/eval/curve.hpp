// The TPR-FDR curve of one map over its thresholds, and its area (docs/definitions.md, Confusion counts and AUC).
#pragma once

#include <vector>

#include "confusion.hpp"

namespace occsweep {

struct CurvePoint {
  double fdr = 0.0;
  double tpr = 0.0;
};

/// Areas under the TPR-FDR curve. NaN when no point is valid.
struct CurveArea {
  double anchored = 0.0;  ///< (0,0) + points sorted by FDR, ties by TPR + (1, TPR of the last): trapezoids
  double observed = 0.0;  ///< trapezoids over the sorted points alone (0 for a single point)
  int points = 0;         ///< valid points used
};

/// The curve's points in threshold order, with points whose TPR or FDR is NaN discarded (paper Section 4.4).
[[nodiscard]] std::vector<CurvePoint> curvePoints(const std::vector<ConfusionCounts>& counts);

[[nodiscard]] CurveArea curveArea(std::vector<CurvePoint> points);

}  // namespace occsweep
