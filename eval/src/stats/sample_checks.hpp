// Input checks shared by the statistics sources (private to occsweep_stats).
#pragma once

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace occsweep::stats::detail {

/// Throws std::invalid_argument naming `what` when a value is NaN or infinite.
inline void requireFinite(const std::vector<double>& values, const char* what) {
  for (std::size_t i = 0; i < values.size(); ++i)
    if (!std::isfinite(values[i]))
      throw std::invalid_argument(std::string(what) + ": value " + std::to_string(i) + " is not finite");
}

inline void requireNonEmpty(const std::vector<double>& values, const char* what) {
  if (values.empty()) throw std::invalid_argument(std::string(what) + ": no values");
}

/// The values that are not exactly zero, in input order (SciPy's zero_method="wilcox").
inline std::vector<double> nonZero(const std::vector<double>& values) {
  std::vector<double> kept;
  for (double v : values)
    if (v != 0.0) kept.push_back(v);
  return kept;
}

}  // namespace occsweep::stats::detail
