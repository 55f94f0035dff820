#include "occsweep/sweeps/results_diff.hpp"

namespace occsweep {

std::vector<std::string> resultDifferences(const ResultsFile& expected, const ResultsFile& actual,
                                           double auc_tolerance) {
  const ResultsDiff diff = diffResults(expected, actual, auc_tolerance);
  std::vector<std::string> out;
  for (const auto& d : diff.header)
    out.push_back("header: " + d.field + " " + d.candidate + ", expected " + d.golden);
  for (const auto& d : diff.combinations) {
    std::string where = d.map_index ? "map " + std::to_string(*d.map_index) : std::string("extra");
    if (d.id) where += ", id " + std::to_string(*d.id);
    out.push_back(where + " (" + d.combination + "): " + d.field + " " + d.candidate + ", expected " + d.golden);
  }
  return out;
}

}  // namespace occsweep
