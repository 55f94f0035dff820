#include "occsweep/stats/effect_size.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "occsweep/stats/wilcoxon.hpp"
#include "sample_checks.hpp"

namespace occsweep::stats {

namespace {

double medianOf(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const std::size_t half = values.size() / 2;
  return values.size() % 2 == 1 ? values[half] : (values[half - 1] + values[half]) / 2.0;
}

/// (W+ - W-) / (W+ + W-), the ranks of |d| over the non-zero differences (Kerby 2014).
double rankBiserial(const std::vector<double>& differences) {
  const auto non_zero = detail::nonZero(differences);
  if (non_zero.empty()) return 0.0;
  std::vector<double> magnitudes(non_zero.size());
  std::transform(non_zero.begin(), non_zero.end(), magnitudes.begin(), [](double v) { return std::fabs(v); });
  const auto ranks = midRanks(magnitudes);
  double plus = 0.0, minus = 0.0;
  for (std::size_t i = 0; i < non_zero.size(); ++i) (non_zero[i] > 0.0 ? plus : minus) += ranks[i];
  return (plus - minus) / (plus + minus);
}

}  // namespace

PairedEffectSize pairedEffectSize(const std::vector<double>& differences) {
  detail::requireNonEmpty(differences, "effect size");
  detail::requireFinite(differences, "effect size");
  PairedEffectSize effect;
  effect.mean_difference =
      std::accumulate(differences.begin(), differences.end(), 0.0) / double(differences.size());
  effect.median_difference = medianOf(differences);
  effect.rank_biserial = rankBiserial(differences);
  return effect;
}

}  // namespace occsweep::stats
