#include <cmath>
#include <map>

#include "occsweep/sweeps/results.hpp"

namespace occsweep {
namespace {

bool aucClose(double a, double b, double tolerance) {
  if (std::isnan(a) || std::isnan(b)) return std::isnan(a) && std::isnan(b);
  return std::abs(a - b) <= tolerance;
}

}  // namespace

std::vector<std::string> resultDifferences(const ResultsFile& expected, const ResultsFile& actual,
                                           double auc_tolerance) {
  std::vector<std::string> diffs;
  std::string why;
  if (!sameWork(expected.header, actual.header, true, &why)) diffs.push_back("header: " + why);
  std::map<std::uint64_t, const MapResult*> by_index;
  for (const auto& m : actual.maps) by_index[m.map_index] = &m;
  if (expected.maps.size() != actual.maps.size())
    diffs.push_back("map count " + std::to_string(actual.maps.size()) + ", expected " +
                    std::to_string(expected.maps.size()));
  for (const auto& e : expected.maps) {
    const std::string where = "map " + std::to_string(e.map_index);
    auto it = by_index.find(e.map_index);
    if (it == by_index.end()) {
      diffs.push_back(where + ": missing");
      continue;
    }
    const MapResult& a = *it->second;
    if (a.thresholds.size() != e.thresholds.size()) {
      diffs.push_back(where + ": threshold count differs");
      continue;
    }
    for (std::size_t i = 0; i < e.thresholds.size(); ++i) {
      const auto& et = e.thresholds[i];
      const auto& at = a.thresholds[i];
      if (et.id != at.id || et.p_t != at.p_t || !(et.counts == at.counts))
        diffs.push_back(where + ", id " + std::to_string(et.id) + ": TP/FP/FN/TN " + std::to_string(at.counts.tp) +
                        "/" + std::to_string(at.counts.fp) + "/" + std::to_string(at.counts.fn) + "/" +
                        std::to_string(at.counts.tn) + ", expected " + std::to_string(et.counts.tp) + "/" +
                        std::to_string(et.counts.fp) + "/" + std::to_string(et.counts.fn) + "/" +
                        std::to_string(et.counts.tn));
    }
    if (!aucClose(e.area.anchored, a.area.anchored, auc_tolerance) ||
        !aucClose(e.area.observed, a.area.observed, auc_tolerance))
      diffs.push_back(where + ": AUC differs by more than " + std::to_string(auc_tolerance));
  }
  return diffs;
}

}  // namespace occsweep
