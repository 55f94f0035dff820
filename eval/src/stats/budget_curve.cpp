#include "occsweep/stats/budget_curve.hpp"

#include <algorithm>

#include "sample_checks.hpp"

namespace occsweep::stats {

namespace {

/// E[max of n] for ascending `sorted`. The weights w_i = C(i-1, n-1) / C(N, n) (1-based i) start at
/// w_N = n / N and follow w_{i-1} = w_i (i - n) / (i - 1) downwards: every factor is in [0, 1], so nothing
/// overflows and underflow only drops weights below 1e-308. Written as top - sum w_i (top - a_i), the result
/// never exceeds the grid's best and is exact for a constant grid.
double expectedBestOf(const std::vector<double>& sorted, std::size_t n) {
  const std::size_t count = sorted.size();
  const double top = sorted.back();
  double weight = double(n) / double(count);
  double shortfall = 0.0;
  for (std::size_t i = count; i >= n && weight > 0.0; --i) {
    shortfall += weight * (top - sorted[i - 1]);
    if (i == n) break;
    weight *= double(i - n) / double(i - 1);
  }
  return top - shortfall;
}

}  // namespace

std::vector<double> expectedBestCurve(std::vector<double> aucs) {
  detail::requireNonEmpty(aucs, "budget curve");
  detail::requireFinite(aucs, "budget curve");
  std::sort(aucs.begin(), aucs.end());
  std::vector<double> curve(aucs.size());
  for (std::size_t n = 1; n <= aucs.size(); ++n) curve[n - 1] = expectedBestOf(aucs, n);
  return curve;
}

std::optional<std::size_t> firstBudgetAbove(const std::vector<double>& curve, double value) {
  for (std::size_t n = 1; n <= curve.size(); ++n)
    if (curve[n - 1] > value) return n;
  return std::nullopt;
}

}  // namespace occsweep::stats
