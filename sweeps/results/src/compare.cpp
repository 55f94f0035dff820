#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <sstream>

#include "occsweep/sweeps/compare.hpp"

namespace occsweep {

double ComparisonRow::improvementPercent(const std::string& method, const std::string& baseline) const {
  const auto m = best(method), b = best(baseline);
  if (!m || !b || !(b->auc > 0)) return std::numeric_limits<double>::quiet_NaN();
  return (m->auc - b->auc) / b->auc * 100.0;
}

std::optional<BestMap> ComparisonRow::best(const std::string& method) const {
  const auto it = best_of.find(method);
  return it == best_of.end() ? std::nullopt : std::optional<BestMap>(it->second);
}

std::vector<std::string> comparedMethods(const std::vector<ComparisonRow>& rows) {
  std::set<std::string> names;
  for (const ComparisonRow& row : rows)
    for (const auto& [name, _] : row.best_of) names.insert(name);
  return {names.begin(), names.end()};
}

std::vector<ComparisonRow> compareBest(const std::vector<ResultsFile>& files) {
  std::map<std::string, ComparisonRow> rows;  // by data-set content hash: one point cloud set each
  std::vector<std::string> order;
  for (std::size_t i = 0; i < files.size(); ++i) {
    const ResultsHeader& h = files[i].header;
    auto [it, fresh] = rows.try_emplace(h.dataset_hash);
    ComparisonRow& row = it->second;
    if (fresh) {
      order.push_back(h.dataset_hash);
      row.dataset = h.dataset_name;
      row.dataset_hash = h.dataset_hash;
      row.point_cloud_set = pointCloudSetOf(h);
      row.provenance = h.point_cloud_set.value("provenance", nlohmann::json());
    }
    row.files_of[h.method].push_back(i);
    std::optional<BestMap> best = row.best(h.method);
    for (const MapResult& m : files[i].maps)
      if (isBetterBest(m.area.anchored, best ? std::optional(best->auc) : std::nullopt))
        best = BestMap{m.area.anchored, m.area.observed, m.params, m.map_index, i};
    if (best) row.best_of.insert_or_assign(h.method, *best);
  }
  std::vector<ComparisonRow> out;
  for (const auto& hash : order) out.push_back(rows.at(hash));
  return out;
}

namespace {

// The settings of a file that two results of one data set must share; with the rule's (variant, statistics mode)
// where files of one method are set side by side.
std::string settingsText(const ResultsHeader& h, bool with_rule) {
  std::ostringstream s;
  s << "resolution " << h.map.resolution << " m, s_c " << h.map.s_c << " m";
  if (with_rule) s << ", variant " << toText(h.map.variant) << ", stats " << toText(h.map.stats);
  return s.str();
}

}  // namespace

std::string mixedTruths(const std::vector<ResultsFile>& files, const std::vector<std::string>& names) {
  for (std::size_t i = 1; i < files.size(); ++i)
    if (files[i].header.truth != files[0].header.truth)
      return names[0] + " (map.truth " + truthModeName(files[0].header.truth) + ") and " + names[i] +
             " (map.truth " + truthModeName(files[i].header.truth) +
             "): results of full and observable truth count different voxels and cannot be mixed";
  return "";
}

std::vector<std::string> mixedSettings(const std::vector<ResultsFile>& files, const std::vector<std::string>& names) {
  std::vector<std::string> problems;
  std::map<std::string, std::size_t> first_of_hash, first_of_method;
  for (std::size_t i = 0; i < files.size(); ++i) {
    const ResultsHeader& h = files[i].header;
    if (h.selection.shard_count != 1)
      problems.push_back(names[i] + ": shard " + std::to_string(h.selection.shard_index) + "/" +
                         std::to_string(h.selection.shard_count) + " of grid " + h.grid_name +
                         ", not the whole grid: its best AUC is the best of part of the grid (occsweep merge the "
                         "shards first)");
    if (h.selection.group)
      problems.push_back(names[i] + ": group " + std::to_string(h.selection.group->index) + "/" +
                         std::to_string(h.selection.group->count) + " (Eq. 16, seed " +
                         std::to_string(h.selection.group->seed) + ") of grid " + h.grid_name +
                         ", not the whole grid: its best AUC is the best of a random part of the grid");
    const auto [same, fresh] = first_of_hash.try_emplace(h.dataset_hash, i);
    const ResultsHeader& o = files[same->second].header;
    if (!fresh && (o.map.resolution != h.map.resolution || o.map.s_c != h.map.s_c))
      problems.push_back(names[i] + " (" + settingsText(h, false) + ") and " + names[same->second] + " (" +
                         settingsText(o, false) + "): another resolution or s_c on the same data set");
    // One file per method and set (of two, compareBest would take the better best AUC without a word); what else
    // differs between them first, which says more.
    if (const auto [j, fresh] = first_of_method.try_emplace(h.dataset_hash + '\n' + h.method, i); !fresh) {
      const ResultsHeader& mo = files[j->second].header;
      if (mo.map.variant != h.map.variant || mo.map.stats != h.map.stats)
        problems.push_back(names[i] + " (" + settingsText(h, true) + ") and " + names[j->second] + " (" +
                           settingsText(mo, true) + "): another variant or statistics mode of method " + h.method +
                           " on the same data set");
      problems.push_back(names[j->second] + " and " + names[i] + ": two results of method " + h.method +
                         " for one data set (" + h.dataset_name + ", hash " + h.dataset_hash + "), " +
                         (names[j->second] == names[i] ? "the same file given twice" : "the better best AUC of "
                                                                                        "the two would be taken"));
    }
  }
  return problems;
}

std::string missingReason(const ComparisonRow& row, const std::string& method, const std::vector<ResultsFile>& files,
                          const std::vector<std::string>& names) {
  if (row.best(method)) return "";
  const auto given = row.files_of.find(method);
  if (given == row.files_of.end()) {
    // Rows are data-set contents (hash): a file of the same name but other scans, region or truth is not compared.
    for (std::size_t i = 0; i < files.size(); ++i) {
      const ResultsHeader& h = files[i].header;
      if (h.dataset_name == row.dataset && h.dataset_hash != row.dataset_hash && h.method == method)
        return method + ": " + names[i] + " is of data set " + row.dataset + " with other contents (hash " +
               h.dataset_hash + ", not " + row.dataset_hash + ": other scans, region or truth), so not compared";
    }
    return method + ": no results file of this method given for data set " + row.dataset;
  }
  std::string why = method + ": no AUC in " + names[given->second.front()];
  const ResultsFile& file = files[given->second.front()];
  const bool no_truth = !file.maps.empty() && file.truth_voxels == 0;
  return why + (no_truth ? ": data set " + row.dataset + " has no ground truth (TP+FN = 0), so TPR and AUC are "
                                                         "undefined (add it with occsweep import truth)"
                         : ": every map's AUC is undefined");
}

}  // namespace occsweep
