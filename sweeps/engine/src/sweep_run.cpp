// A sweep: each selected map counted by the sweep's engine (sweep_engine.hpp: replayed from recorded events by
// default, or built directly), thresholded at every p_t.
#include <algorithm>
#include <chrono>
#include <functional>
#include <iterator>
#include <mutex>
#include <filesystem>
#include <iostream>
#include <map>
#include <optional>
#include <set>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "occsweep/core/method_registry.hpp"
#include "occsweep/eval/coordinates.hpp"
#include "occsweep/eval/dataset.hpp"
#include "occsweep/eval/bounded_read.hpp"
#include "occsweep/sweeps/progress.hpp"
#include "occsweep/sweeps/results_store.hpp"
#include "occsweep/sweeps/sweep.hpp"
#include "occsweep/sweeps/sweep_engine.hpp"
#include "occsweep/sweeps/version.hpp"
#include "sweep_internal.hpp"

namespace occsweep {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

using Clock = std::chrono::steady_clock;

// The truths a sweep counts (docs/results-format.md, "Truth").
struct SweepTruths {
  GroundTruth full;
  GroundTruth marked;  // unobservable voxels in `excluded` under observable truth or with a twin; else full
  [[nodiscard]] const GroundTruth& counted(TruthMode mode) const { return mode == TruthMode::Full ? full : marked; }
};

// Maps finished before, read from the partial log of an interrupted run.
struct FinishedMaps {
  std::map<std::uint64_t, MapResult> done, twin_done;
  std::map<std::uint64_t, std::string> engine_of;  // provenance of every finished map
};

// Maps counted by this run, in the order of the work.
struct CountedMaps {
  std::vector<MapResult> maps, twin;
};

bool hasTwin(const SweepConfig& c) { return !c.observable_out.empty(); }

// Observable truth: the unobservable truth voxels leave the evaluation. With a twin (observable_out) they are marked
// and both truths are counted from the same maps. Computed before anything is written: a region refused (past its
// limit, or holding no voxel) leaves no partial file.
SweepTruths sweepTruths(const SweepConfig& c, const Dataset& data) {
  SweepTruths t;
  t.full = groundTruthOf(data, c.dataset, c.resolution);
  const bool twin = hasTwin(c);
  if (twin && c.truth != TruthMode::Full) throw std::invalid_argument("sweep: observable_out needs full truth");
  t.marked = evaluatedTruth(twin ? TruthMode::Observable : c.truth, t.full, data.scans, c.s_c);
  return t;
}

ResultsHeader sweepHeader(const SweepConfig& c, const GridSpec& grid, const GridEnumeration& e, const Dataset& data,
                          const SweepEngine& engine) {
  ResultsHeader h;
  h.version = kVersion;
  h.commit = kGitCommit;
  h.grid_name = grid.name;
  h.grid_hash = grid.file_hash;
  h.method = grid.method;
  h.parameters = grid.layout;
  h.grid_combinations = e.combinations;
  h.selection = c.selection;
  h.dataset_name = data.name;
  h.dataset_hash = datasetContentHash(c.dataset);
  h.point_cloud_set = data.source;
  h.resolution = c.resolution;
  h.s_c = c.s_c;
  h.variant = toText(c.variant);
  h.stats = toText(c.stats);
  h.engine = engine.name();
  h.truth = c.truth;
  return h;
}

ResultsHeader twinHeader(ResultsHeader h) {
  h.truth = TruthMode::Observable;
  return h;
}

// The same sweep's own complete file (and twin) is returned as it is; anything else at `out` is refused unless
// --force, and only occsweep's results are replaced even then (docs/robustness.md, "Outputs, temporaries and
// --force"). The twin too replaces only occsweep's own results (a user's file there is refused before any work).
std::optional<ResultsFile> checkOutputs(const SweepConfig& c, const ResultsHeader& h) {
  std::error_code ec;
  if (fs::exists(fs::symlink_status(c.out, ec))) {
    checkOutputTarget(c.out, true, resultsOutput());
    ResultsFile old = readResults(c.out);
    std::string why;
    if (!sameWork(old.header, h, true, &why) && !c.force)
      throw std::runtime_error(c.out.string() + ": holds results of other work (" + why +
                               "); --force replaces it, or choose another --out");
    if (why.empty() && old.complete &&
        (!hasTwin(c) || sweep_detail::completeResultsOf(c.observable_out, twinHeader(h)))) {
      fs::remove(c.out.string() + ".partial.jsonl", ec);  // superseded: a kill came between the rename and this
      return old;
    }
  }
  if (hasTwin(c) && fs::exists(fs::symlink_status(c.observable_out, ec)))
    checkOutputTarget(c.observable_out, true, resultsOutput());
  return std::nullopt;
}

// The selected maps not finished before, with the p_t values of their selected thresholds.
std::vector<MapToCount> mapsToCount(const std::vector<const SweepItem*>& todo, const GridEnumeration& e) {
  std::vector<MapToCount> maps;
  for (const SweepItem* item : todo) {
    MapToCount& m = maps.emplace_back();
    m.params = &e.maps[item->map_index];
    for (std::size_t t : item->thresholds) m.p_t.push_back(toDouble(e.thresholds[item->map_index][t]));
  }
  return maps;
}

MapResult mapResult(const SweepItem& item, const GridEnumeration& e, const std::vector<ConfusionCounts>& counts,
                    double seconds) {
  MapResult r;
  r.map_index = item.map_index;
  r.params = e.maps[item.map_index];
  for (std::size_t t = 0; t < item.thresholds.size(); ++t)
    r.thresholds.push_back({e.first_id[item.map_index] + item.thresholds[t],
                            e.thresholds[item.map_index][item.thresholds[t]], counts[t]});
  r.area = mapArea(r.thresholds);
  r.seconds = seconds;
  return r;
}

MapResult withCounts(MapResult r, const std::vector<ConfusionCounts>& counts) {
  for (std::size_t t = 0; t < r.thresholds.size(); ++t) r.thresholds[t].counts = counts[t];
  r.area = mapArea(r.thresholds);
  return r;
}

// Receives each counted batch's maps (and, with a twin, their observable-truth counts), from several threads.
using BatchSink = std::function<void(std::vector<MapResult>&& maps, std::vector<MapResult>&& twin,
                                     const std::vector<std::size_t>& batch)>;

// Counts every map of `todo` with the engine, its batches in parallel, each batch handed to `sink` as it finishes.
void countMaps(const SweepEngine& engine, const std::vector<const SweepItem*>& todo,
               const std::vector<MapToCount>& maps, const GridEnumeration& e, const ResultsHeader& h, bool twin,
               bool quiet, const BatchSink& sink, tbb::task_arena& arena) {
  const std::vector<std::vector<std::size_t>> batches = engine.batches(findMethod(h.method), h.parameters, maps);
  Progress progress("sweep " + h.grid_name + " on " + h.dataset_name + " (" + engine.name() + ")", todo.size(),
                    quiet);
  arena.execute([&] {
    tbb::parallel_for(std::size_t(0), batches.size(), [&](std::size_t b) {
      const auto t0 = Clock::now();
      const std::vector<std::size_t>& batch = batches[b];
      const BatchCounts counts = engine.count(maps, batch);
      // A batch's time shared by its maps.
      const double seconds = std::chrono::duration<double>(Clock::now() - t0).count() / double(batch.size());
      std::vector<MapResult> results, twins;
      for (std::size_t j = 0; j < batch.size(); ++j) {
        results.push_back(mapResult(*todo[batch[j]], e, counts.counts[j], seconds));
        if (twin) twins.push_back(withCounts(results.back(), counts.observable[j]));
      }
      sink(std::move(results), std::move(twins), batch);
      for (std::size_t j = 0; j < batch.size(); ++j) progress.advance();
    });
  });
}

// The JSON path's sink: each finished map logged at once (with its engine, for provenance across resumes:
// docs/results-format.md) and kept for the file written at the end.
CountedMaps countIntoLog(const SweepEngine& engine, const std::vector<const SweepItem*>& todo,
                         const std::vector<MapToCount>& maps, const GridEnumeration& e, const ResultsHeader& h,
                         bool twin, bool quiet, sweep_detail::PartialLog& log, tbb::task_arena& arena) {
  CountedMaps out;
  out.maps.resize(todo.size());
  out.twin.resize(twin ? todo.size() : 0);
  countMaps(engine, todo, maps, e, h, twin, quiet,
            [&](std::vector<MapResult>&& results, std::vector<MapResult>&& twins, const std::vector<std::size_t>& batch) {
              for (std::size_t j = 0; j < batch.size(); ++j) {
                json line = toJson(results[j], h.parameters);
                line["engine"] = engine.name();
                if (twin) {
                  const json oj = toJson(twins[j], h.parameters);
                  line[sweep_detail::kTwinField] = {{"thresholds", oj.at("thresholds")}, {"auc", oj.at("auc")}};
                  out.twin[batch[j]] = std::move(twins[j]);
                }
                log.append(line);
                out.maps[batch[j]] = std::move(results[j]);
              }
            },
            arena);
  return out;
}

// Every engine that made a map of the file.
void recordEngines(ResultsHeader& h, const FinishedMaps& finished, const std::string& engine) {
  std::set<std::string> engines;
  for (const auto& [index, name] : finished.engine_of)
    if (finished.done.count(index)) engines.insert(name);
  if (engines.empty()) engines.insert(engine);
  setEngines(h, engines);
}

// The results file (and twin), complete: the maps finished before and now.
ResultsFile finishSweep(ResultsHeader h, FinishedMaps& finished, CountedMaps counted, const std::string& engine) {
  for (auto& r : counted.maps) finished.engine_of[r.map_index] = engine, finished.done[r.map_index] = std::move(r);
  for (auto& r : counted.twin) finished.twin_done[r.map_index] = std::move(r);
  recordEngines(h, finished, engine);
  ResultsFile f;
  f.header = std::move(h);
  for (auto& [_, r] : finished.done) f.maps.push_back(std::move(r));
  f.complete = true;
  return f;
}

// Writes the files atomically, the twin first: a complete main file promises a complete twin. A failed write
// takes the partial log with it (a full disk).
void writeSweepResults(const ResultsFile& f, FinishedMaps& finished, const SweepConfig& c,
                       sweep_detail::PartialLog& log) {
  try {
    if (hasTwin(c)) {
      ResultsFile o;
      o.header = twinHeader(f.header);
      for (auto& [_, r] : finished.twin_done) o.maps.push_back(std::move(r));
      o.complete = true;
      o.seconds = f.seconds;
      writeResults(o, c.observable_out);
    }
    writeResults(f, c.out);
  } catch (const OutputError&) {
    log.dropOnError();
    throw;
  }
  log.remove();
}

}  // namespace

namespace {

// What every sweep reads and derives before counting: the grid, its selection, the data set and its truths.
struct SweepSetup {
  GridSpec grid;
  GridEnumeration e;
  std::vector<SweepItem> items;
  std::unique_ptr<SweepEngine> engine;
  Dataset data;  // not const: replay frees the points once recorded
  SweepTruths truths;
  ResultsHeader header;
};

SweepSetup setUpSweep(const SweepConfig& c) {
  SweepSetup s;
  s.grid = loadGrid(resolveGridPath(c.grid));
  s.e = enumerateGrid(s.grid);
  s.items = selectWork(s.grid, s.e, c.selection);
  s.engine = makeSweepEngine(c.engine);
  s.data = readDataset(c.dataset);
  requireInKeyRange(s.data, c.dataset, c.resolution);
  s.truths = sweepTruths(c, s.data);
  s.header = sweepHeader(c, s.grid, s.e, s.data, *s.engine);
  return s;
}

// The selected maps not among `done`.
std::vector<const SweepItem*> unfinished(const std::vector<SweepItem>& items, const std::vector<std::uint64_t>& done) {
  std::vector<const SweepItem*> todo;
  for (const auto& item : items)
    if (!std::binary_search(done.begin(), done.end(), item.map_index)) todo.push_back(&item);
  return todo;
}

// Records the events (replay) or readies the direct builds of the maps to count.
SweepInputs prepareEngine(const SweepConfig& c, SweepSetup& s, const std::vector<MapToCount>& maps,
                          tbb::task_arena& arena) {
  const SweepInputs inputs{c, findMethod(s.grid.method), s.grid.layout, s.data.scans, s.truths.counted(c.truth),
                           s.truths.marked, hasTwin(c)};
  arena.execute([&] { s.engine->prepare(inputs, maps); });
  return inputs;
}

void reportResume(const SweepConfig& c, const fs::path& partial, std::size_t done, std::size_t of) {
  if (done > 0 && !c.quiet)
    std::cerr << "resuming " << partial.string() << ": " << done << " of " << of << " maps done before\n";
}

SweepSummary summaryOf(const ResultsHeader& h, std::uint64_t maps, std::uint64_t combinations, double seconds) {
  return {h, maps, combinations, seconds};
}

// ---------------------------------------------------------------------------------------------------------
// Into a store (docs/results-format.md, "Results store"): every batch is one transaction of OUT.partial, which is
// what a killed sweep resumes from, renamed to OUT once complete. Nothing of the results is held in memory.

// The same sweep's complete store at `out` is left as it is (its header returned); anything else there is refused
// unless --force, and only occsweep's results are replaced even then.
std::optional<ResultsFile> completeStore(const SweepConfig& c, const ResultsHeader& h) {
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(c.out, ec))) return std::nullopt;
  checkOutputTarget(c.out, true, resultsOutput());
  ResultsFile old = readResultsHeader(c.out);
  std::string why;
  if (!sameWork(old.header, h, true, &why) && !c.force)
    throw std::runtime_error(c.out.string() + ": holds results of other work (" + why +
                             "); --force replaces it, or choose another --out");
  if (!why.empty() || !old.complete) return std::nullopt;
  fs::remove(c.out.string() + ".partial", ec);  // superseded: a kill came between the rename and this
  return old;
}

// OUT.partial of the same work, resumed; of other work, refused unless --force (then started anew). It is opened
// for writing first: SQLite rolls back the batch a kill left open. A file there that is not an occsweep store is
// never replaced, except an empty one or one without tables (a kill during create(), which is one transaction).
ResultsStore partialStore(const fs::path& partial, const ResultsHeader& h, bool force) {
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(partial, ec))) return ResultsStore::create(partial, h);
  requireRegularFile(partial);
  std::optional<ResultsStore> old;
  try {
    old.emplace(ResultsStore::open(partial, true));
  } catch (const std::exception& e) {
    if (fs::file_size(partial, ec) != 0 && hasTables(partial))
      throw std::runtime_error(partial.string() + ": not an occsweep results store (" + e.what() +
                               "); remove it, or choose another --out");
  }
  std::string why;
  if (old && sameWork(old->header(), h, true, &why)) return std::move(*old);
  if (old && !force)
    throw std::runtime_error(partial.string() + ": an interrupted sweep of other work (" + why +
                             "); --force replaces it, or choose another --out");
  old.reset();
  fs::remove(partial);
  return ResultsStore::create(partial, h);
}

// Finished maps into the store from the counting threads: one transaction a second at most (or per 4,096 maps),
// since each commit waits for the disk. A kill loses at most that second of work (docs/results-format.md).
class StoreWriter {
 public:
  StoreWriter(ResultsStore& store, std::string engine) : store_(store), engine_(std::move(engine)) {}
  void add(std::vector<MapResult>&& maps) {
    const std::lock_guard lock(mutex_);
    std::move(maps.begin(), maps.end(), std::back_inserter(pending_));
    if (pending_.size() >= kMaxPending || Clock::now() - last_commit_ >= std::chrono::seconds(1)) commit();
  }
  void flush() {
    const std::lock_guard lock(mutex_);
    commit();
  }

 private:
  static constexpr std::size_t kMaxPending = 4096;
  void commit() {
    if (!pending_.empty()) store_.append(pending_, engine_);
    pending_.clear();
    last_commit_ = Clock::now();
  }
  ResultsStore& store_;
  std::string engine_;
  std::mutex mutex_;
  std::vector<MapResult> pending_;
  Clock::time_point last_commit_ = Clock::now();
};

SweepSummary sweepIntoStore(const SweepConfig& c) {
  const auto start = Clock::now();
  if (hasTwin(c)) throw std::invalid_argument("sweep: observable_out is written as JSON only (a results store has no twin)");
  SweepSetup s = setUpSweep(c);
  std::uint64_t combinations = 0;
  for (const SweepItem& item : s.items) combinations += item.thresholds.size();
  if (std::optional<ResultsFile> complete = completeStore(c, s.header))
    return summaryOf(complete->header, s.items.size(), combinations, complete->seconds);
  if (c.out.has_parent_path()) fs::create_directories(c.out.parent_path());
  const fs::path partial = c.out.string() + ".partial";
  ResultsStore store = partialStore(partial, s.header, c.force);
  const std::vector<std::uint64_t> done = store.mapIndices();
  reportResume(c, partial, done.size(), s.items.size());
  const std::vector<const SweepItem*> todo = unfinished(s.items, done);

  tbb::task_arena arena(c.threads > 0 ? c.threads : tbb::task_arena::automatic);
  const std::vector<MapToCount> maps = mapsToCount(todo, s.e);
  prepareEngine(c, s, maps, arena);
  StoreWriter writer(store, s.engine->name());
  countMaps(*s.engine, todo, maps, s.e, s.header, false, c.quiet,
            [&](std::vector<MapResult>&& results, std::vector<MapResult>&&, const std::vector<std::size_t>&) {
              writer.add(std::move(results));
            },
            arena);
  writer.flush();

  const std::vector<std::string> engines = store.engineNames();
  setEngines(s.header, {engines.begin(), engines.end()});
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  store.finish(s.header, seconds);
  { ResultsStore closed = std::move(store); }
  fs::rename(partial, c.out);
  return summaryOf(s.header, s.items.size(), combinations, seconds);
}

// ---------------------------------------------------------------------------------------------------------
// Into JSON: finished maps logged to OUT.partial.jsonl, the file written whole at the end (small results).

ResultsFile sweepIntoJson(const SweepConfig& c) {
  const auto start = Clock::now();
  SweepSetup s = setUpSweep(c);
  const ResultsHeader& h = s.header;
  if (std::optional<ResultsFile> complete = checkOutputs(c, h)) return std::move(*complete);

  const fs::path partial = c.out.string() + ".partial.jsonl";
  FinishedMaps finished;
  finished.done = sweep_detail::loadPartial(partial, h, c.force, finished.engine_of,
                                            hasTwin(c) ? &finished.twin_done : nullptr);
  std::vector<std::uint64_t> done;
  for (const auto& [index, _] : finished.done) done.push_back(index);
  reportResume(c, partial, done.size(), s.items.size());
  const std::vector<const SweepItem*> todo = unfinished(s.items, done);
  if (c.out.has_parent_path()) fs::create_directories(c.out.parent_path());
  sweep_detail::PartialLog log(partial, h, finished.done.size());

  tbb::task_arena arena(c.threads > 0 ? c.threads : tbb::task_arena::automatic);
  const std::vector<MapToCount> maps = mapsToCount(todo, s.e);
  prepareEngine(c, s, maps, arena);
  CountedMaps counted = countIntoLog(*s.engine, todo, maps, s.e, h, hasTwin(c), c.quiet, log, arena);

  ResultsFile f = finishSweep(h, finished, std::move(counted), s.engine->name());
  f.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  writeSweepResults(f, finished, c, log);
  return f;
}

}  // namespace

ResultsFile runSweep(const SweepConfig& c) {
  if (!isStorePath(c.out)) return sweepIntoJson(c);
  (void)sweepIntoStore(c);
  return readResults(c.out);
}

SweepSummary sweepToFile(const SweepConfig& c) {
  if (isStorePath(c.out)) return sweepIntoStore(c);
  const ResultsFile f = sweepIntoJson(c);
  std::uint64_t combinations = 0;
  for (const MapResult& m : f.maps) combinations += m.thresholds.size();
  return summaryOf(f.header, f.maps.size(), combinations, f.seconds);
}

}  // namespace occsweep
