// Grids that nest (docs/statistics.md, "Grids that nest"): the sets and units where a method's results hold the
// baseline's best map, and the optima verdict of the units that do not nest, worded.
#pragma once

#include <cstddef>
#include <set>
#include <string>
#include <vector>

#include "occsweep/stats/verdict.hpp"
#include "occsweep/sweeps/compare.hpp"

namespace occsweep::nesting {

struct Nesting {
  std::size_t sets = 0;         ///< sets paired with the baseline where some result of the method holds its best
  std::set<std::string> units;  ///< the units every paired set of which does
};

/// Where any of the method's results for a set (every file given for it) holds a map whose anchored and observed
/// AUCs equal the baseline's best on that set; units as `unit_of_row` names them.
[[nodiscard]] Nesting nestingOf(const std::vector<ComparisonRow>& rows, const std::vector<ResultsFile>& files,
                                const std::string& method, const std::string& baseline,
                                const std::vector<std::string>& unit_of_row);

/// The optima verdict of a method `nested` of whose `units` (named `unit_name`) nest: `kept`, the verdict over the
/// others, saying so, or "at least the baseline by construction" when they are too few to tell (then with the
/// basis of `over_all`, the verdict over every unit); `over_all` itself when every unit is too few to tell.
[[nodiscard]] stats::Verdict nestedVerdict(const stats::Verdict& kept, const stats::Verdict& over_all,
                                           std::size_t units, std::size_t nested, const std::string& unit_name,
                                           const std::string& baseline);

}  // namespace occsweep::nesting
