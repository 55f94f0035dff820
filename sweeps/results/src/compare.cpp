#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <sstream>

#include "occsweep/sweeps/merge.hpp"

namespace occsweep {

double ComparisonRow::improvementPercent() const { return improvementPercent("knn"); }

double ComparisonRow::improvementPercent(const std::string& method, const std::string& baseline) const {
  const auto m = best(method), b = best(baseline);
  if (!m || !b || !(b->auc > 0)) return std::numeric_limits<double>::quiet_NaN();
  return (m->auc - b->auc) / b->auc * 100.0;
}

std::optional<BestMap> ComparisonRow::best(const std::string& method) const {
  if (method == "octomap") return octomap;
  if (method == "knn") return knn;
  const auto it = others.find(method);
  return it == others.end() ? std::nullopt : std::optional<BestMap>(it->second);
}

std::vector<std::string> otherMethods(const std::vector<ComparisonRow>& rows) {
  std::set<std::string> names;
  for (const ComparisonRow& row : rows)
    for (const auto& [name, _] : row.others) names.insert(name);
  return {names.begin(), names.end()};
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
    const bool knn = h.method == "knn";
    std::optional<BestMap> other;
    if (h.method != "knn" && h.method != "octomap" && row.others.count(h.method)) other = row.others.at(h.method);
    auto& best = knn ? row.knn : (h.method == "octomap" ? row.octomap : other);
    if (knn || h.method == "octomap") (knn ? row.knn_files : row.octomap_files).push_back(std::size_t(&f - files.data()));
    for (const auto& m : f.maps) {
      if (!isBetterBest(m.area.anchored, best ? std::optional(best->auc) : std::nullopt)) continue;
      best = BestMap{m.area.anchored, m.area.observed, m.params, m.map_index, std::size_t(&f - files.data())};
    }
    if (other) row.others.insert_or_assign(h.method, *other);
  }
  std::vector<ComparisonRow> out;
  for (const auto& hash : order) out.push_back(rows.at(hash));
  return out;
}

namespace {

std::string settingsText(const ResultsHeader& h) {
  std::ostringstream s;
  s << "resolution " << h.resolution << " m, s_c " << h.s_c << " m";
  if (h.method == "knn") s << ", variant " << h.variant << ", stats " << h.stats;
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
  std::map<std::string, std::size_t> first_of_hash, first_knn_of_hash, first_of_method;
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
    if (!fresh && (o.resolution != h.resolution || o.s_c != h.s_c))
      problems.push_back(names[i] + " (" + settingsText(h) + ") and " + names[same->second] + " (" + settingsText(o) +
                         "): another resolution or s_c on the same data set");
    if (h.method == "knn") {
      const auto [k, k_fresh] = first_knn_of_hash.try_emplace(h.dataset_hash, i);
      const ResultsHeader& ko = files[k->second].header;
      if (!k_fresh && (ko.variant != h.variant || ko.stats != h.stats))
        problems.push_back(names[i] + " (" + settingsText(h) + ") and " + names[k->second] + " (" + settingsText(ko) +
                           "): another k-NN variant or statistics mode on the same data set");
    }
    // One file per method and set (of two, compareBest would take the better best AUC without a word); after the
    // reasons above, which say more.
    if (const auto [j, fresh] = first_of_method.try_emplace(h.dataset_hash + '\n' + h.method, i); !fresh)
      problems.push_back(names[j->second] + " and " + names[i] + ": two results of method " + h.method +
                         " for one data set (" + h.dataset_name + ", hash " + h.dataset_hash + "), " +
                         (names[j->second] == names[i] ? "the same file given twice" : "the better best AUC of "
                                                                                        "the two would be taken"));
  }
  return problems;
}

std::string missingReason(const ComparisonRow& row, bool knn, const std::vector<ResultsFile>& files,
                          const std::vector<std::string>& names) {
  if (knn ? row.knn.has_value() : row.octomap.has_value()) return "";
  const auto& given = knn ? row.knn_files : row.octomap_files;
  const std::string method = knn ? "k-NN" : "OctoMap";
  if (given.empty()) {
    // Rows are data-set contents (hash): a file of the same name but other scans, region or truth is not compared.
    for (std::size_t i = 0; i < files.size(); ++i) {
      const ResultsHeader& h = files[i].header;
      if (h.dataset_name == row.dataset && h.dataset_hash != row.dataset_hash && (h.method == (knn ? "knn" : "octomap")))
        return method + ": " + names[i] + " is of data set " + row.dataset + " with other contents (hash " +
               h.dataset_hash + ", not " + row.dataset_hash + ": other scans, region or truth), so not compared";
    }
    return method + ": no results file of this method given for data set " + row.dataset;
  }
  std::string why = method + ": no AUC in " + names[given.front()];
  const ResultsFile& file = files[given.front()];
  const bool no_truth = !file.maps.empty() && file.truth_voxels == 0;
  return why + (no_truth ? ": data set " + row.dataset + " has no ground truth (TP+FN = 0), so TPR and AUC are "
                                                         "undefined (add it with occsweep import truth)"
                         : ": every map's AUC is undefined");
}

}  // namespace occsweep
