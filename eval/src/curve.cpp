#include "occsweep/eval/curve.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace occsweep {

std::vector<CurvePoint> curvePoints(const std::vector<ConfusionCounts>& counts) {
  std::vector<CurvePoint> points;
  for (const auto& c : counts) {
    const double tpr = c.tpr(), fdr = c.fdr();
    if (std::isnan(tpr) || std::isnan(fdr)) continue;  // discarded, as the paper does (Section 4.4)
    points.push_back({fdr, tpr});
  }
  return points;
}

CurveArea curveArea(std::vector<CurvePoint> points) {
  CurveArea area;
  area.points = int(points.size());
  if (points.empty()) {
    area.anchored = area.observed = std::numeric_limits<double>::quiet_NaN();
    return area;
  }
  std::sort(points.begin(), points.end(), [](const CurvePoint& a, const CurvePoint& b) {
    return a.fdr < b.fdr || (a.fdr == b.fdr && a.tpr < b.tpr);
  });
  auto trapezoids = [](const std::vector<CurvePoint>& p) {
    double sum = 0.0;
    for (std::size_t i = 1; i < p.size(); ++i) sum += (p[i].fdr - p[i - 1].fdr) * (p[i].tpr + p[i - 1].tpr) / 2.0;
    return sum;
  };
  area.observed = trapezoids(points);
  std::vector<CurvePoint> anchored;
  anchored.reserve(points.size() + 2);
  anchored.push_back({0.0, 0.0});
  anchored.insert(anchored.end(), points.begin(), points.end());
  anchored.push_back({1.0, points.back().tpr});
  area.anchored = trapezoids(anchored);
  return area;
}

}  // namespace occsweep
