#include <cmath>
#include <limits>
#include <map>

#include "occsweep/sweeps/merge.hpp"

namespace occsweep {

double ComparisonRow::improvementPercent() const {
  if (!octomap || !knn || !(octomap->auc > 0)) return std::numeric_limits<double>::quiet_NaN();
  return (knn->auc - octomap->auc) / octomap->auc * 100.0;
}

std::vector<ComparisonRow> compareBest(const std::vector<ResultsFile>& files) {
  std::map<std::string, ComparisonRow> rows;  // by data-set content hash: one point cloud set each
  std::vector<std::string> order;
  for (const auto& f : files) {
    const auto& h = f.header;
    auto [it, fresh] = rows.try_emplace(h.dataset_hash);
    ComparisonRow& row = it->second;
    if (fresh) {
      order.push_back(h.dataset_hash);
      row.dataset = h.dataset_name;
      row.dataset_hash = h.dataset_hash;
      const auto& pcs = h.point_cloud_set;
      row.point_cloud_set = pcs.contains("pcs_id") ? pcs.at("pcs_id").dump() : "-";
    }
    auto& best = h.method == GridMethod::Knn ? row.knn : row.octomap;
    for (const auto& m : f.maps) {
      // Ties keep the first (lowest map index): stable across runs.
      if (std::isnan(m.area.anchored) || (best && !(m.area.anchored > best->auc))) continue;
      best = BestMap{m.area.anchored, m.area.observed, m.params, m.map_index};
    }
  }
  std::vector<ComparisonRow> out;
  for (const auto& hash : order) out.push_back(rows.at(hash));
  return out;
}

}  // namespace occsweep
