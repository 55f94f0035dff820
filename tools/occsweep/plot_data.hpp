// What `occsweep plot` draws, as JSON (its --json, and the input of share/occsweep/plot_results.py): computed here
// from results files, so that every number in a figure can be read back (docs/statistics.md, "Figures").
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "occsweep/sweeps/compare_statistics.hpp"

namespace occsweep::cli {

/// The figures `occsweep plot` makes.
inline const std::vector<std::string> kPlotKinds = {"curves", "budget", "improvement", "params"};

/// The sets drawn in one curves figure at most (small multiples stay readable in print).
inline constexpr std::size_t kMaxCurveSets = 12;

struct PlotInputs {
  const std::vector<ComparisonRow>& rows;
  const std::vector<ResultsFile>& files;
  std::string baseline;  ///< improvement, budget: every method against it
  std::string method;    ///< params: the method whose grid is drawn
};

/// TPR against FDR of each method's best map on each set (at most kMaxCurveSets sets).
[[nodiscard]] nlohmann::json curvesData(const PlotInputs& in);
/// Each method's mean budget curve, and the baseline's mean best.
[[nodiscard]] nlohmann::json budgetData(const PlotInputs& in);
/// Fig. 5 for any method: per set, the baseline's best AUC and the method's improvement, with the mean's interval.
[[nodiscard]] nlohmann::json improvementData(const PlotInputs& in);
/// The marginal of the AUC over the grid: for each parameter value, the mean and the best AUC of the maps with it.
[[nodiscard]] nlohmann::json paramsData(const PlotInputs& in);

/// The data of `kind` (one of kPlotKinds).
[[nodiscard]] nlohmann::json plotData(const std::string& kind, const PlotInputs& in);

}  // namespace occsweep::cli
