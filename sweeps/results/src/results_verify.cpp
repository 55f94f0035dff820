// Everything a results file claims, checked (docs/results-format.md): a hand edit, a merge gone wrong or a
// truncated selection cannot pass for a complete sweep.
#include "occsweep/sweeps/results_verify.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <set>
#include <stdexcept>

#include "occsweep/core/method_registry.hpp"
#include "occsweep/io/bounded_read.hpp"
#include "occsweep/eval/coordinates.hpp"
#include "occsweep/eval/dataset.hpp"
#include "occsweep/sweeps/sharding.hpp"
#include "occsweep/sweeps/results_store.hpp"
#include "occsweep/sweeps/selection.hpp"
#include "occsweep/eval/json_input.hpp"

namespace occsweep {
namespace {

// The claims of one file, checked map by map (nothing but the Eq. 16 group's ids is held).
struct Claims {
  const ResultsHeader& h;
  bool complete;
  const std::string& file;
  const MappingMethod* method = nullptr;      // registered: its bounds are checked
  std::vector<MethodParameter> parameters;
  std::vector<ParameterRelation> relations;
  std::vector<std::uint64_t> group_ids;       // a complete group's ids, when small enough to list
  std::uint64_t total = 0, truth = 0, ids = 0;
  std::optional<std::uint64_t> last_map, last_id;

  Claims(const ResultsHeader& header, bool is_complete, const std::string& name)
      : h(header), complete(is_complete), file(name) {
    try {
      method = &findMethod(h.method);
      parameters = method->parameters();
      relations = method->relations();
    } catch (const std::invalid_argument&) {
      // another program's method: its bounds are not known here
    }
    if (complete && h.selection.shard_count == 1 && h.selection.group && h.grid_combinations <= kMaxCheckedPermutation) {
      GridEnumeration shape;
      shape.combinations = h.grid_combinations;
      group_ids = expectedIds(shape, h.selection);
    }
  }

  [[noreturn]] void fail(const std::string& where, const std::string& rule) const {
    throw std::runtime_error(file + ": " + where + ": " + rule);
  }

  void settings() const {
    // The settings were checked as the header was read (parseMapSettings).
    if (h.grid_combinations == 0) fail("grid.combinations", "must be at least 1");
    if (h.selection.shard_count > h.grid_combinations)
      fail("selection.shard.count", "is more than the grid's " + std::to_string(h.grid_combinations) + " combinations");
    if (h.selection.group && h.selection.group->count > h.grid_combinations)
      fail("selection.group.count", "is more than the grid's " + std::to_string(h.grid_combinations) +
                                        " combinations (every Eq. 16 group holds at least one)");
  }

  // `where` (a callable) names the field only on a failure: built for each of millions of thresholds, the names
  // took an eighth of `compare`'s time on a 3.2 M-combination store.
  void probability(Fixed v, const auto& where) const {
    if (v < 0 || v > kFixedScale) fail(where(), "must be a probability in [0, 1]");
  }

  // Each value within its parameter's bounds and the relations among them (Eq. 12 for OctoMap and k-NN), when this
  // program has the method registered (docs/methods.md).
  void params(const MapResult& m, const std::string& where) const {
    if (m.params.values.size() != h.parameters.names.size()) fail(where + ".params", "has other parameters");
    if (parameters.empty()) return;
    std::vector<double> values;
    for (const Fixed v : m.params.values) values.push_back(toDouble(v));
    if (const std::optional<std::string> why = brokenRelation(parameters, relations, values))
      fail(where + ".params", *why + " (" + h.method + ")");
  }

  // One region for every threshold of every map.
  void counts(const ThresholdResult& r, const auto& tw) {
    const auto& c = r.counts;
    std::uint64_t sum = 0, positives = 0;
    if (__builtin_add_overflow(c.tp, c.fn, &positives) || __builtin_add_overflow(positives, c.fp, &sum) ||
        __builtin_add_overflow(sum, c.tn, &sum) || sum > kMaxRegionVoxels)
      fail(tw(), "TP+FP+FN+TN is more than the 2^48 voxels OctoMap's keys can address");
    if (ids == 1) total = sum, truth = positives;
    if (sum != total)
      fail(tw(), "TP+FP+FN+TN is " + std::to_string(sum) + ", another map of the file counts " + std::to_string(total) +
                   ": every map classifies the same region");
    if (positives != truth)
      fail(tw(), "TP+FN is " + std::to_string(positives) + ", another map of the file counts " + std::to_string(truth) +
                   ": every map has the same true voxels");
  }

  // Maps in increasing index, p_t increasing within a map, ids inside the grid and each at most once. Ids follow
  // map order (a map's ids are contiguous, docs/definitions.md), so increasing ids are unique ids.
  void add(const MapResult& m, std::size_t i) {
    const std::string where = "maps[" + std::to_string(i) + "]";
    if (last_map && m.map_index <= *last_map)
      fail(where + ".map_index", "map " + std::to_string(m.map_index) + " after map " + std::to_string(*last_map) +
                                     ": every map at most once, in increasing order (duplicated map?)");
    last_map = m.map_index;
    if (m.map_index >= h.grid_combinations) fail(where + ".map_index", "is beyond the grid's combinations");
    if (!std::isfinite(m.seconds) || m.seconds < 0) fail(where + ".seconds", "must be a finite number >= 0");
    params(m, where);
    for (std::size_t t = 0; t < m.thresholds.size(); ++t) {
      const ThresholdResult& r = m.thresholds[t];
      const auto tw = [&] { return where + ".thresholds[" + std::to_string(t) + "]"; };
      probability(r.p_t, [&] { return tw() + ".p_t"; });
      if (t > 0 && !(r.p_t > m.thresholds[t - 1].p_t))
        fail(tw() + ".p_t", "thresholds must have increasing p_t, each at most once (duplicated threshold?)");
      if (r.id >= h.grid_combinations) fail(tw() + ".id", "is beyond the grid's combinations");
      if (last_id && r.id <= *last_id)
        fail(tw() + ".id", "id " + std::to_string(r.id) + " after id " + std::to_string(*last_id) +
                             ": ids increase with the map and p_t, each at most once (it appears twice in the file?)");
      last_id = r.id;
      ++ids;
      counts(r, tw);
      if (!group_ids.empty() && !std::binary_search(group_ids.begin(), group_ids.end(), r.id))
        fail(where, "id " + std::to_string(r.id) + " is not in Eq. 16 group " + std::to_string(h.selection.group->index));
    }
  }

  // A complete file of a whole grid or Eq. 16 group holds exactly the selection's ids.
  void finish() const {
    if (!complete || h.selection.shard_count != 1) return;  // a shard's maps need the grid: GridChecker
    const std::uint64_t n = h.grid_combinations;
    std::uint64_t expected = n;
    if (h.selection.group) {
      const auto& g = *h.selection.group;
      const Block b = contiguousBlock(n, g.count, g.index);
      expected = b.end - b.begin;
    }
    if (ids != expected)
      fail("maps", "complete, but holds " + std::to_string(ids) + " combinations of the " + std::to_string(expected) +
                       " its selection claims (a missing map?)");
  }
};

}  // namespace

struct ClaimsChecker::State : Claims {
  using Claims::Claims;
  std::size_t maps = 0;
};

ClaimsChecker::ClaimsChecker(const ResultsHeader& header, bool complete, const std::string& file)
    : state_(std::make_unique<State>(header, complete, file)) {
  state_->settings();
}
ClaimsChecker::~ClaimsChecker() = default;
void ClaimsChecker::add(const MapResult& m) { state_->add(m, state_->maps++); }
void ClaimsChecker::finish() const { state_->finish(); }

void verifyClaims(const ResultsFile& f, const std::string& file) {
  ClaimsChecker check(f.header, f.complete, file);
  for (const MapResult& m : f.maps) check.add(m);
  check.finish();
}

struct GridChecker::State {
  State(const ResultsHeader& header, bool is_complete, std::string name)
      : h(header), complete(is_complete), file(std::move(name)) {}
  const ResultsHeader& h;
  bool complete;
  std::string file;
  bool found = false;
  GridSpec grid;
  GridEnumeration e;
  std::vector<SweepItem> items;  // the selection's maps, in map order
  std::size_t seen = 0;
};

namespace {
[[noreturn]] void missing(const GridChecker::State& s, std::uint64_t map_index) {
  throw std::runtime_error(s.file + ": map " + std::to_string(map_index) + ": missing, though the file says complete");
}
[[noreturn]] void notSelected(const GridChecker::State& s, std::uint64_t map_index) {
  throw std::runtime_error(s.file + ": map " + std::to_string(map_index) + ": not in this file's selection (shard " +
                           std::to_string(s.h.selection.shard_index) + "/" + std::to_string(s.h.selection.shard_count) + ")");
}
}  // namespace

// The grid of the file, when its file is found with the same hash: enumerated, the selection's maps listed.
GridChecker::GridChecker(const ResultsHeader& header, bool complete, const std::string& file)
    : state_(std::make_unique<State>(header, complete, file)) {
  State& s = *state_;
  try {
    s.grid = loadGrid(resolveGridPath(header.grid_name));
  } catch (const std::exception&) {
    return;
  }
  if (s.grid.file_hash != header.grid_hash) return;
  s.e = enumerateSelection(s.grid, header.selection);  // the maps of the file's selection
  if (s.e.combinations != header.grid_combinations)
    throw std::runtime_error(file + ": grid.combinations does not match grid " + s.grid.name);
  if (complete) s.items = selectWork(s.grid, s.e, header.selection);  // only coverage needs the selection's maps
  s.found = true;
}
GridChecker::~GridChecker() = default;
bool GridChecker::found() const { return state_->found; }

// The map is one of the grid's with the grid's parameters, and (complete) one of the selection's with exactly its
// thresholds. Maps come in increasing index (ClaimsChecker), so each selected map is met at most once.
void GridChecker::add(const MapResult& m) {
  State& s = *state_;
  if (!s.found) return;
  const std::string where = s.file + ": map " + std::to_string(m.map_index);
  if (m.map_index >= s.e.map_count) throw std::runtime_error(where + ": no such map in grid " + s.grid.name);
  if (!s.e.holds(m.map_index)) notSelected(s, m.map_index);
  if (s.e.map(m.map_index) != m.params)
    throw std::runtime_error(where + ": parameters differ from the grid's (edited by hand?)");
  const std::uint64_t first = s.e.firstId(m.map_index);
  const auto& p_t = s.e.thresholdsOf(m.map_index);
  for (const auto& t : m.thresholds)
    if (t.id < first || t.id - first >= p_t.size() || p_t[t.id - first] != t.p_t)
      throw std::runtime_error(where + ": id " + std::to_string(t.id) + " is not this map's or has another p_t");
  if (!s.complete) return;
  const auto item = std::lower_bound(s.items.begin(), s.items.end(), m.map_index,
                                     [](const SweepItem& i, std::uint64_t index) { return i.map_index < index; });
  if (item == s.items.end() || item->map_index != m.map_index) notSelected(s, m.map_index);
  if (std::size_t(item - s.items.begin()) != s.seen) missing(s, s.items[s.seen].map_index);
  if (m.thresholds.size() != item->thresholds.size())
    throw std::runtime_error(where + ": holds " + std::to_string(m.thresholds.size()) + " thresholds, its selection " +
                             std::to_string(item->thresholds.size()));
  for (std::size_t t = 0; t < item->thresholds.size(); ++t)
    if (m.thresholds[t].id != first + item->thresholds[t])
      throw std::runtime_error(where + ": threshold " + std::to_string(t) + " has id " +
                               std::to_string(m.thresholds[t].id) + ", not the selection's");
  ++s.seen;
}

void GridChecker::finish() const {
  const State& s = *state_;
  if (s.found && s.complete && s.seen < s.items.size()) missing(s, s.items[s.seen].map_index);
}

struct DatasetChecker::State {
  State(std::string name, std::string folder, TruthMode mode, double res)
      : file(std::move(name)), dir(std::move(folder)), truth(mode), resolution(res) {}
  std::string file, dir;
  TruthMode truth;
  double resolution = 0;
  std::uint64_t region = 0, truth_voxels = 0;
  std::size_t maps = 0;
};

DatasetChecker::DatasetChecker(const ResultsHeader& h, const std::string& file, const std::filesystem::path& dir)
    : state_(std::make_unique<State>(file, dir.string(), h.truth, h.map.resolution)) {
  const std::string hash = datasetContentHash(dir);
  if (hash != h.dataset_hash)
    throw std::runtime_error(file + ": dataset.content_hash: is " + h.dataset_hash + ", " + dir.string() + " has " +
                             hash + ": results of another data set (or of an edited one)");
  const Dataset d = readDataset(dir);
  requireInKeyRange(d, dir, h.map.resolution);
  // Observable truth leaves its unobservable voxels out of the region and of the truth alike.
  const GroundTruth gt =
      evaluatedTruth(h.truth, makeGroundTruth(d.truth, d.region, h.map.resolution), d.scans, h.map.s_c, dir.string());
  state_->region = gt.evaluatedVoxelCount();
  state_->truth_voxels = gt.evaluatedTrueVoxelCount();
}
DatasetChecker::~DatasetChecker() = default;

void DatasetChecker::add(const MapResult& m) {
  const State& s = *state_;
  const std::size_t i = state_->maps++;
  for (std::size_t t = 0; t < m.thresholds.size(); ++t) {
    const auto& c = m.thresholds[t].counts;
    const std::string where = s.file + ": maps[" + std::to_string(i) + "].thresholds[" + std::to_string(t) + "]: ";
    if (c.tp + c.fp + c.fn + c.tn != s.region)
      throw std::runtime_error(where + "TP+FP+FN+TN is " + std::to_string(c.tp + c.fp + c.fn + c.tn) + ", the region of " +
                               s.dir + " holds " + std::to_string(s.region) + " voxels at resolution " +
                               std::to_string(s.resolution) + " m");
    if (c.tp + c.fn != s.truth_voxels)
      throw std::runtime_error(where + "TP+FN is " + std::to_string(c.tp + c.fn) + ", the truth of " + s.dir +
                               " fills " + std::to_string(s.truth_voxels) + " voxels of the region" +
                               (s.truth == TruthMode::Observable ? " observable from its scans" : ""));
  }
}

void verifyAgainstDataset(const ResultsFile& f, const std::string& file, const std::filesystem::path& dir) {
  DatasetChecker check(f.header, file, dir);
  for (const MapResult& m : f.maps) check.add(m);
}

namespace {

// One open of a results file: a store through one connection, a JSON file from one read of its bytes, so that what
// is checked is what is read (a file replaced at its name meanwhile is neither half-checked nor read unchecked).
struct OpenedResults {
  std::optional<ResultsStore> store;
  ResultsFile content;                    // header, completeness, seconds, truth voxels; a JSON file's maps too
  std::vector<std::string> row_engines;   // a store's map rows each name their engine
};

OpenedResults openResults(const std::filesystem::path& file) {
  OpenedResults o;
  if (!isResultsStore(file)) {  // parsed from the one read of its bytes: a store put there meanwhile is no JSON
    o.content = parseResults(readJsonFile(file), file.string());
    return o;
  }
  o.store.emplace(ResultsStore::open(file));
  o.store->verifyIntegrity();
  o.row_engines = o.store->engineNames();
  o.content.header = o.store->header();
  o.content.complete = o.store->complete();
  o.content.seconds = o.store->seconds();
  o.content.truth_voxels = o.store->truthVoxels();
  return o;
}

void forEachOpenedMap(OpenedResults& o, const MapVisitor& visit) {
  if (o.store) return o.store->forEachMap(MapDetail::Full, visit);
  std::vector<MapResult> maps = std::move(o.content.maps);
  for (MapResult& m : maps) visit(std::move(m));
}

void checkOpenedHeader(const OpenedResults& o, const std::string& name) {
  const ResultsFile& head = o.content;
  // Each map row's engine among those the header names; "mixed" when exported from a mixed JSON file, which records
  // no engine per map.
  for (const std::string& e : o.row_engines)
    if (std::find(head.header.engines.begin(), head.header.engines.end(), e) == head.header.engines.end() &&
        !(e == "mixed" && head.header.engine == "mixed"))
      throw std::runtime_error(name + ": maps.engine: '" + e + "' is not among the engines map.engines names "
                               "(edited by hand?)");
  if (!head.complete) throw std::runtime_error(name + ": incomplete results (the sweep did not finish)");
  if (!std::isfinite(head.seconds) || head.seconds < 0)
    throw std::runtime_error(name + ": seconds: must be a finite number >= 0");
}

}  // namespace

ResultsCheck readCheckedResults(const std::filesystem::path& file, const std::filesystem::path& dataset,
                                const MapVisitor& visit, ResultsFile* header) {
  const std::string name = file.string();
  OpenedResults opened = openResults(file);
  checkOpenedHeader(opened, name);
  ResultsCheck out;
  out.header = opened.content.header;
  if (header) {  // everything but the maps, which go to `visit`
    header->header = opened.content.header;
    header->complete = opened.content.complete;
    header->seconds = opened.content.seconds;
    header->truth_voxels = opened.content.truth_voxels;
  }
  ClaimsChecker claims(out.header, true, name);
  GridChecker grid(out.header, true, name);
  std::optional<DatasetChecker> data;
  if (!dataset.empty()) data.emplace(out.header, name, dataset);
  forEachOpenedMap(opened, [&](MapResult&& m) {
    claims.add(m);
    grid.add(m);
    if (data) data->add(m);
    ++out.maps;
    out.combinations += m.thresholds.size();
    if (visit) visit(std::move(m));
  });
  claims.finish();
  grid.finish();
  out.grid_checked = grid.found();
  return out;
}

ResultsCheck checkResultsFile(const std::filesystem::path& file, const std::filesystem::path& dataset) {
  return readCheckedResults(file, dataset, {}, nullptr);
}

ResultsFile readCheckedResults(const std::filesystem::path& file, MapDetail detail) {
  ResultsFile f;
  (void)readCheckedResults(file, "", [&](MapResult&& m) {
    if (detail == MapDetail::Summary) m.dropThresholds();
    f.maps.push_back(std::move(m));
  }, &f);
  return f;
}

}  // namespace occsweep
