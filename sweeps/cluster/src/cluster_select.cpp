// `cluster select`: one folder of links per data set, pcs-NNNN and rank-N, over the rankings of every generation
// block, so that sweep tasks planned before generation can name "the 800th ranked point cloud set" (paper 4.3).
#include <algorithm>
#include <cmath>
#include <fstream>
#include <set>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "occsweep/eval/bounded_read.hpp"
#include "occsweep/sweeps/cluster_select.hpp"
#include "occsweep/sweeps/results.hpp"

namespace occsweep {
namespace fs = std::filesystem;
namespace {

struct RankedSet {
  std::string folder;
  fs::path path;  ///< absolute
  std::uint64_t id = 0;
  double fdr = NAN, tpr = NAN;
};

double number(const nlohmann::json& j, const char* key) {
  return j.contains(key) && j[key].is_number() ? j[key].get<double>() : NAN;
}

/// The generator's order (stereo rankSets, `ranked_by` in ranking.json): naive FDR ascending with NaN last, then
/// TPR descending when both are numbers, then id; merging blocks by the same key gives the ranking of all sets.
bool better(const RankedSet& a, const RankedSet& b) {
  if (std::isnan(a.fdr) != std::isnan(b.fdr)) return !std::isnan(a.fdr);
  if (!std::isnan(a.fdr) && a.fdr != b.fdr) return a.fdr < b.fdr;
  if (!std::isnan(a.tpr) && !std::isnan(b.tpr) && a.tpr != b.tpr) return a.tpr > b.tpr;  // as rankSets does
  return a.id < b.id;
}

// A folder `selectRanked` wrote: sets.json of its format and the links it lists (each set's folder and rank-N),
// nothing else. A re-run replaces it; a folder holding anything more is not occsweep's to remove
// (docs/robustness.md, "Ownership").
bool isSelectionFolder(const fs::path& dir) {
  std::set<std::string> links;
  try {
    if (!jsonOutput("", "occsweep-selected-sets").is_own(dir / "sets.json")) return false;
    const nlohmann::json sets = readJsonFile(dir / "sets.json");
    for (const auto& s : sets.at("sets")) {
      links.insert(s.at("folder").get<std::string>());
      links.insert("rank-" + std::to_string(s.at("rank").get<std::uint64_t>()));
    }
  } catch (const std::exception&) {
    return false;
  }
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name != "sets.json" && (!it->is_symlink() || !links.contains(name))) return false;
  }
  return !ec;
}

// `cluster select` has no --force: it replaces its own folder of links and nothing else, so a folder that is not its
// own is refused with what to do instead (checkOutputTarget would say "even with --force").
void requireOwnSelectionFolder(const fs::path& target) {
  std::error_code ec;
  const fs::file_status status = fs::symlink_status(target, ec);
  const bool empty_folder = fs::is_directory(status) && fs::is_empty(target, ec);
  if (!fs::exists(status) || fs::is_symlink(status) || empty_folder || isSelectionFolder(target)) return;
  throw OutputError(target.string() + ": exists and is not occsweep's folder of selected point cloud sets (its "
                    "sets.json and the links that lists, nothing else); nothing was changed: move or remove it, or "
                    "give --out another path");
}

}  // namespace

std::size_t selectRanked(const std::vector<fs::path>& rankings, const fs::path& out) {
  std::vector<RankedSet> sets;
  std::set<std::uint64_t> ids;
  for (const auto& file : rankings) {
    const std::string text = readFileBytes(file);  // refuses folders and FIFOs by name
    nlohmann::json j;
    try {
      j = nlohmann::json::parse(text);
      if (j.value("format", "") != "occsweep-pointcloud-ranking")
        throw std::runtime_error("format: expected \"occsweep-pointcloud-ranking\"");
      for (const auto& s : j.at("sets")) {
        RankedSet r{s.at("folder").get<std::string>(), {}, s.at("id").get<std::uint64_t>(), NAN, NAN};
        // The folder names a link in --out: one name, never a path that leads elsewhere (docs/cluster.md).
        if (const fs::path f(r.folder); r.folder.empty() || f.filename() != f || r.folder == "." || r.folder == "..")
          throw std::runtime_error("sets: folder '" + r.folder + "' is not a single folder name beside the ranking "
                                   "(no '/', not '.' or '..')");
        r.path = fs::absolute(file).parent_path() / r.folder;
        if (s.contains("naive")) {
          r.fdr = number(s["naive"], "fdr");
          r.tpr = number(s["naive"], "tpr");
        }
        if (!fs::is_directory(r.path)) throw std::runtime_error("sets: folder " + r.folder + " not found");
        if (!ids.insert(r.id).second) throw std::runtime_error("sets: id " + std::to_string(r.id) + " in two rankings");
        sets.push_back(r);
      }
    } catch (const std::exception& e) {
      throw std::runtime_error(file.string() + ": " + e.what());
    }
  }
  if (sets.empty()) throw std::runtime_error("no point cloud sets in the rankings");
  std::stable_sort(sets.begin(), sets.end(), better);
  // Built beside `out` and renamed into place: a killed task leaves no half folder.
  const fs::path target = fs::absolute(out);
  requireOwnSelectionFolder(target);
  checkOutputTarget(target, true, {"folder of selected point cloud sets", isSelectionFolder});
  OutputFolder folder(target);
  const fs::path& tmp = folder.path();
  nlohmann::json list = nlohmann::json::array();
  for (std::size_t r = 0; r < sets.size(); ++r) {
    const fs::path link = fs::relative(sets[r].path, target);
    makeSymlinkChecked(link, tmp / sets[r].folder);
    makeSymlinkChecked(link, tmp / ("rank-" + std::to_string(r + 1)));
    list.push_back({{"rank", r + 1}, {"id", sets[r].id}, {"folder", sets[r].folder}, {"path", link.string()}});
  }
  // Written in the temporary folder directly: an interrupt that removed the folder makes this write fail, where
  // an atomic write would make the folder again.
  writeFileChecked(tmp / "sets.json", nlohmann::json{{"format", "occsweep-selected-sets"}, {"sets", list}}.dump(1) + '\n');
  folder.commit();
  return sets.size();
}

}  // namespace occsweep
