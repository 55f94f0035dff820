#include <set>
#include <algorithm>
#include <map>
#include <stdexcept>

#include "occsweep/core/limits.hpp"
#include "occsweep/sweeps/merge.hpp"
#include "occsweep/sweeps/results_verify.hpp"
#include "occsweep/sweeps/selection.hpp"

namespace occsweep {

std::vector<std::uint64_t> coveredIds(const ResultsFile& f) {
  std::vector<std::uint64_t> ids;
  for (const auto& m : f.maps)
    for (const auto& t : m.thresholds) ids.push_back(t.id);
  return ids;
}

bool checkAgainstGrid(const ResultsFile& f, const std::string& file) {
  GridSpec grid;
  try {
    grid = loadGrid(resolveGridPath(f.header.grid_name));
  } catch (const std::exception&) {
    return false;
  }
  if (grid.file_hash != f.header.grid_hash) return false;
  const GridEnumeration e = enumerateGrid(grid);
  if (e.combinations != f.header.grid_combinations)
    throw std::runtime_error(file + ": grid.combinations does not match grid " + grid.name);
  for (const auto& m : f.maps) {
    const std::string where = file + ": map " + std::to_string(m.map_index);
    if (m.map_index >= e.maps.size()) throw std::runtime_error(where + ": no such map in grid " + grid.name);
    const MapParams& g = e.maps[m.map_index];
    const MapParams& p = m.params;
    if (g != p)
      throw std::runtime_error(where + ": parameters differ from the grid's (edited by hand?)");
    for (const auto& t : m.thresholds) {
      const std::uint64_t first = e.first_id[m.map_index];
      if (t.id < first || t.id - first >= e.thresholds[m.map_index].size() ||
          e.thresholds[m.map_index][t.id - first] != t.p_t)
        throw std::runtime_error(where + ": id " + std::to_string(t.id) + " is not this map's or has another p_t");
    }
  }
  verifyCoverage(f, grid, e, file);
  return true;
}

ResultsFile mergeResults(const std::vector<std::filesystem::path>& files) {
  if (files.empty()) throw std::runtime_error("merge: no input files");
  std::vector<ResultsFile> in;
  for (const auto& file : files) {
    in.push_back(readResults(file));
    if (!in.back().complete) throw std::runtime_error(file.string() + ": incomplete results (the sweep did not finish)");
    std::string why;
    if (!sameWork(in.front().header, in.back().header, false, &why))
      throw std::runtime_error(file.string() + ": foreign results: " + why + " than " + files.front().string());
    checkAgainstGrid(in.back(), file.string());
  }
  // Every id of the selection exactly once.
  std::map<std::uint64_t, std::size_t> owner;
  ResultsFile out;
  out.header = in.front().header;
  std::set<std::string> engines;  // provenance: every engine of every shard
  for (const auto& f : in) engines.insert(f.header.engines.begin(), f.header.engines.end());
  setEngines(out.header, engines);
  out.header.selection.shard_index = 0;
  out.header.selection.shard_count = 1;
  GridEnumeration shape;  // only the count is needed for the expected ids
  shape.combinations = out.header.grid_combinations;
  // Without the grid file the count is only what the file claims (issue 13: a 15 KB file claiming 3e8 took
  // 2.4 GB): bounded like an enumeration before the expected ids are listed.
  try {
    checkLimit("grid.combinations", shape.combinations, limits().combinations, "--max-combinations");
  } catch (const LimitError& e) {
    throw std::runtime_error(files.front().string() + ": " + e.what());
  }
  const auto expected = expectedIds(shape, out.header.selection);
  for (std::size_t i = 0; i < in.size(); ++i) {
    for (std::uint64_t id : coveredIds(in[i])) {
      if (!std::binary_search(expected.begin(), expected.end(), id))
        throw std::runtime_error(files[i].string() + ": foreign combination id " + std::to_string(id) +
                                 " (not in this grid's selection)");
      auto [it, fresh] = owner.emplace(id, i);
      if (!fresh)
        throw std::runtime_error(files[i].string() + ": combination id " + std::to_string(id) + " duplicated (also in " +
                                 files[it->second].string() + ")");
    }
    for (auto& m : in[i].maps) out.maps.push_back(std::move(m));
    out.seconds += in[i].seconds;
  }
  if (owner.size() != expected.size()) {
    std::string first;
    for (std::uint64_t id : expected)
      if (!owner.count(id)) {
        first = std::to_string(id);
        break;
      }
    throw std::runtime_error("merge: " + std::to_string(expected.size() - owner.size()) +
                             " combinations missing (first id " + first + "): a shard is missing");
  }
  std::sort(out.maps.begin(), out.maps.end(), [](const auto& a, const auto& b) { return a.map_index < b.map_index; });
  out.complete = true;
  return out;
}

}  // namespace occsweep
