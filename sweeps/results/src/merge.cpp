#include <set>
#include <algorithm>
#include <functional>
#include <map>
#include <optional>
#include <stdexcept>

#include "occsweep/core/limits.hpp"
#include "occsweep/sweeps/merge.hpp"
#include "occsweep/sweeps/results_store.hpp"
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
  GridChecker check(f.header, f.complete, file);
  for (const MapResult& m : f.maps) check.add(m);
  check.finish();
  return check.found();
}

namespace {

using MergedMapSink = std::function<void(MapResult&&)>;
constexpr std::size_t kMergeBatch = 4096;  // maps per transaction of a merged store

// Each input's header (read once), and the merged header of complete results of one work: the first file's, every
// shard's engines, the whole selection.
struct MergeHeaders {
  std::vector<ResultsFile> inputs;
  ResultsFile merged;
};

MergeHeaders mergeHeaders(const std::vector<std::filesystem::path>& files) {
  if (files.empty()) throw std::runtime_error("merge: no input files");
  std::vector<ResultsFile> heads;
  std::set<std::string> engines;  // provenance: every engine of every shard
  ResultsFile out;
  for (const auto& file : files) {
    (void)checkResultsFile(file, "");  // what `results check` refuses is never merged (docs/results-format.md)
    heads.push_back(readResultsHeader(file));
    if (!heads.back().complete)
      throw std::runtime_error(file.string() + ": incomplete results (the sweep did not finish)");
    std::string why;
    if (!sameWork(heads.front().header, heads.back().header, false, &why))
      throw std::runtime_error(file.string() + ": foreign results: " + why + " than " + files.front().string());
    engines.insert(heads.back().header.engines.begin(), heads.back().header.engines.end());
    out.seconds += heads.back().seconds;
  }
  out.header = heads.front().header;
  setEngines(out.header, engines);
  out.header.selection.shard_index = 0;
  out.header.selection.shard_count = 1;
  out.complete = true;
  return {std::move(heads), std::move(out)};
}

// The combinations of the merged file's grid as its header claims them. Without the grid file that count is only
// what the file claims (a 15 KB file can claim 3e8, which would take 2.4 GB): bounded like an enumeration before
// anything is allocated for it.
std::uint64_t boundedGridCombinations(const ResultsHeader& merged, const std::filesystem::path& first_file) {
  try {
    checkLimit("grid.combinations", merged.grid_combinations, limits().combinations, "--max-combinations");
  } catch (const LimitError& e) {
    throw std::runtime_error(first_file.string() + ": " + e.what());
  }
  return merged.grid_combinations;
}

// The ids of the merged file's Eq. 16 group (only the grid's count is needed for them).
std::vector<std::uint64_t> groupIds(const ResultsHeader& merged) {
  GridEnumeration shape;
  shape.combinations = merged.grid_combinations;
  return expectedIds(shape, merged.selection);
}

// Every id of the selection exactly once over the files: a bit per combination of the grid.
class IdOwners {
 public:
  IdOwners(const ResultsHeader& merged, const std::filesystem::path& first_file)
      : n_(boundedGridCombinations(merged, first_file)) {
    if (merged.selection.group) group_ = groupIds(merged);
    owner_.assign(n_, 0);
  }
  void claim(std::uint64_t id, std::size_t file, const std::vector<std::filesystem::path>& files) {
    if (id >= n_ || (!group_.empty() && !std::binary_search(group_.begin(), group_.end(), id)))
      throw std::runtime_error(files[file].string() + ": foreign combination id " + std::to_string(id) +
                               " (not in this grid's selection)");
    if (owner_[id] != 0)
      throw std::runtime_error(files[file].string() + ": combination id " + std::to_string(id) + " duplicated (also in " +
                               files[owner_[id] - 1].string() + ")");
    owner_[id] = std::uint32_t(file + 1);
    ++claimed_;
  }
  void requireAll() const {
    const std::uint64_t expected = group_.empty() ? n_ : group_.size();
    if (claimed_ == expected) return;
    std::uint64_t first = 0;
    if (group_.empty()) {
      while (owner_[first] != 0) ++first;
    } else {
      for (std::uint64_t id : group_)
        if (owner_[id] == 0) {
          first = id;
          break;
        }
    }
    throw std::runtime_error("merge: " + std::to_string(expected - claimed_) + " combinations missing (first id " +
                             std::to_string(first) + "): a shard is missing");
  }

 private:
  std::uint64_t n_ = 0, claimed_ = 0;
  std::vector<std::uint64_t> group_;  // an Eq. 16 group's ids; empty: the whole grid
  std::vector<std::uint32_t> owner_;  // 1 + the file holding each id; 0: none yet
};

// Streams every map of every file to `sink`, each id owned once. Each file is read once with every check of
// `results check` (readCheckedResults), and must still hold the work its header was merged as: a file replaced at
// its name since is refused, never merged unchecked (docs/results-format.md, "Reading").
void mergeMaps(const std::vector<std::filesystem::path>& files, const MergeHeaders& heads, const MergedMapSink& sink) {
  IdOwners owners(heads.merged.header, files.front());
  for (std::size_t i = 0; i < files.size(); ++i) {
    ResultsFile read;
    (void)readCheckedResults(files[i], "", [&](MapResult&& m) {
      for (const ThresholdResult& t : m.thresholds) owners.claim(t.id, i, files);
      sink(std::move(m));
    }, &read);
    std::string why;
    if (!sameWork(heads.inputs[i].header, read.header, true, &why))
      throw std::runtime_error(files[i].string() + ": changed while it was merged: " + why);
  }
  owners.requireAll();
}

}  // namespace

ResultsFile mergeResults(const std::vector<std::filesystem::path>& files) {
  std::vector<MapResult> maps;
  const MergeHeaders heads = mergeHeaders(files);
  mergeMaps(files, heads, [&](MapResult&& m) { maps.push_back(std::move(m)); });
  ResultsFile out = heads.merged;
  std::sort(maps.begin(), maps.end(), [](const auto& a, const auto& b) { return a.map_index < b.map_index; });
  out.maps = std::move(maps);
  return out;
}

namespace {

// The combinations the merged file holds: its grid's, or its Eq. 16 group's (every shard merged).
std::uint64_t mergedCombinations(const ResultsHeader& merged, const std::filesystem::path& first_file) {
  const std::uint64_t grid = boundedGridCombinations(merged, first_file);
  return merged.selection.group ? groupIds(merged).size() : grid;
}

// A merge into JSON is built in memory: past kMaxJsonCombinations it is refused from the first file's header (the
// merged file holds its grid's or its Eq. 16 group's combinations), before any file is checked or read in full.
void refuseLargeJson(const std::vector<std::filesystem::path>& files, const std::filesystem::path& out) {
  if (files.empty()) return;  // mergeHeaders says so
  const std::string merge = "the merge of " + std::to_string(files.size()) + (files.size() == 1 ? " file" : " files");
  occsweep::refuseLargeJson(out, merge, mergedCombinations(readResultsHeader(files.front()).header, files.front()));
}

}  // namespace

std::uint64_t mergeResultsInto(const std::vector<std::filesystem::path>& files, const std::filesystem::path& out) {
  if (!isStorePath(out)) {
    refuseLargeJson(files, out);
    const ResultsFile merged = mergeResults(files);
    writeResults(merged, out);
    return merged.maps.size();
  }
  const MergeHeaders heads = mergeHeaders(files);
  const ResultsFile& merged = heads.merged;
  requireNoJournalBeside(out);
  OutputFile file(out);  // its empty temporary becomes the store: removed on an error or an interrupt
  std::uint64_t maps = 0;
  {
    ResultsStore store = ResultsStore::create(file.temporary(), merged.header, StoreUse::Temporary);
    std::vector<MapResult> batch;
    mergeMaps(files, heads, [&](MapResult&& m) {
      batch.push_back(std::move(m));
      if (batch.size() == kMergeBatch) store.append(batch, merged.header.engine), batch.clear();
      ++maps;
    });
    if (!batch.empty()) store.append(batch, merged.header.engine);
    store.finish(merged.header, merged.seconds);
  }
  file.commit();
  return maps;
}

}  // namespace occsweep
