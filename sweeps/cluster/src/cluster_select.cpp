// `cluster select`: one folder of links per data set, pcs-NNNN and rank-N, over the rankings of every generation
// block, so that sweep tasks planned before generation can name "the 800th ranked point cloud set" (paper 4.3).
#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <set>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "occsweep/io/bounded_read.hpp"
#include "occsweep/sweeps/cluster_select.hpp"
#include "occsweep/sweeps/results.hpp"
#include "occsweep/eval/json_input.hpp"
#include "occsweep/io/output_target.hpp"

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
// (docs/io.md, "Ownership").
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

/// The fields of ranking.json that name the generation whose sets it ranks (writeRanking,
/// tools/stereo/src/ranking.cpp): one data set, scale, seed, point cloud grid and options. Sets of two generations
/// are not one data set's ranking (docs/cluster.md, "Decisions the definitions leave open").
constexpr std::array<const char*, 5> kGenerationFields = {"dataset", "scale", "seed", "pointcloud_grid", "options"};

nlohmann::json generationOf(const nlohmann::json& ranking) {
  nlohmann::json generation = nlohmann::json::object();
  for (const char* field : kGenerationFields)
    if (ranking.contains(field)) generation[field] = ranking[field];
  return generation;
}

/// Refuses a ranking of another generation than the first one's, naming both files and the first field that differs.
void requireSameGeneration(const nlohmann::json& generation, const nlohmann::json& first, const fs::path& first_file) {
  const auto shown = [](const nlohmann::json& g, const char* field) {
    return g.contains(field) ? g[field].dump() : std::string("none recorded");
  };
  for (const char* field : kGenerationFields)
    if (shown(generation, field) != shown(first, field))
      throw std::runtime_error(std::string(field) + " " + shown(generation, field) + ", but " + first_file.string() +
                               " has " + shown(first, field) + ": select ranks the blocks of one data set's "
                               "generation together; give only rankings of the same data set, scale, seed, point "
                               "cloud grid and options (nothing was written)");
}

/// `cluster select` has no --force: it replaces only a folder it wrote (isSelectionFolder); anything else at --out is
/// refused, saying what to do (a link is refused by checkOutputTarget).
void requireNoOtherFolder(const fs::path& out) {
  std::error_code ec;
  const fs::file_status st = fs::symlink_status(out, ec);
  const bool empty_folder = fs::is_directory(st) && fs::is_empty(out, ec);
  if (!fs::exists(st) || fs::is_symlink(st) || empty_folder || isSelectionFolder(out)) return;
  throw std::runtime_error(out.string() + ": exists and is not occsweep's folder of selected point cloud sets (its "
                           "sets.json and the links it lists, nothing else), the only folder select replaces: move it "
                           "away, or give another --out (nothing was written)");
}

}  // namespace

std::size_t selectRanked(const std::vector<fs::path>& rankings, const fs::path& out) {
  std::vector<RankedSet> sets;
  std::set<std::uint64_t> ids;
  nlohmann::json generation;
  for (const auto& file : rankings) {
    const std::string text = readFileBytes(file);  // refuses folders and FIFOs by name
    nlohmann::json j;
    try {
      j = nlohmann::json::parse(text);
      if (j.value("format", "") != "occsweep-pointcloud-ranking")
        throw std::runtime_error("format: expected \"occsweep-pointcloud-ranking\"");
      if (generation.is_null()) generation = generationOf(j);  // the first ranking's
      requireSameGeneration(generationOf(j), generation, rankings.front());
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
  requireNoOtherFolder(target);
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
  nlohmann::json selected = generation;  // which data set's sets these are
  selected["format"] = "occsweep-selected-sets";
  selected["sets"] = list;
  writeFileChecked(tmp / "sets.json", selected.dump(1) + '\n');
  folder.commit();
  return sets.size();
}

}  // namespace occsweep
