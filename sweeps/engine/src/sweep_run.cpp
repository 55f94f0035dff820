// A sweep: each selected map counted by the sweep's engine (sweep_engine.hpp: replayed from recorded events by
// default, or built directly), thresholded at every p_t.
#include <chrono>
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
#include "occsweep/sweeps/progress.hpp"
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

// Counts every map of `todo` with the engine, its batches in parallel, each finished map logged at once (with its
// engine, for provenance across resumes: docs/results-format.md).
CountedMaps countMaps(const SweepEngine& engine, const std::vector<const SweepItem*>& todo,
                      const std::vector<MapToCount>& maps, const GridEnumeration& e, const ResultsHeader& h,
                      bool twin, bool quiet, sweep_detail::PartialLog& log, tbb::task_arena& arena) {
  const std::vector<std::vector<std::size_t>> batches = engine.batches(findMethod(h.method), h.parameters, maps);
  CountedMaps out;
  out.maps.resize(todo.size());
  out.twin.resize(twin ? todo.size() : 0);
  Progress progress("sweep " + h.grid_name + " on " + h.dataset_name + " (" + engine.name() + ")", todo.size(),
                    quiet);
  arena.execute([&] {
    tbb::parallel_for(std::size_t(0), batches.size(), [&](std::size_t b) {
      const auto t0 = Clock::now();
      const std::vector<std::size_t>& batch = batches[b];
      const BatchCounts counts = engine.count(maps, batch);
      // A batch's time shared by its maps.
      const double seconds = std::chrono::duration<double>(Clock::now() - t0).count() / double(batch.size());
      for (std::size_t j = 0; j < batch.size(); ++j) {
        MapResult r = mapResult(*todo[batch[j]], e, counts.counts[j], seconds);
        json line = toJson(r, h.parameters);
        line["engine"] = engine.name();
        if (twin) {
          MapResult o = withCounts(r, counts.observable[j]);
          const json oj = toJson(o, h.parameters);
          line[sweep_detail::kTwinField] = {{"thresholds", oj.at("thresholds")}, {"auc", oj.at("auc")}};
          out.twin[batch[j]] = std::move(o);
        }
        log.append(line);
        out.maps[batch[j]] = std::move(r);
        progress.advance();
      }
    });
  });
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

ResultsFile runSweep(const SweepConfig& c) {
  const auto start = Clock::now();
  const GridSpec grid = loadGrid(resolveGridPath(c.grid));
  const GridEnumeration e = enumerateGrid(grid);
  const std::vector<SweepItem> items = selectWork(grid, e, c.selection);
  const std::unique_ptr<SweepEngine> engine = makeSweepEngine(c.engine);
  Dataset data = readDataset(c.dataset);  // not const: replay frees the points once recorded
  requireInKeyRange(data, c.dataset, c.resolution);
  const SweepTruths truths = sweepTruths(c, data);
  const ResultsHeader h = sweepHeader(c, grid, e, data, *engine);
  if (std::optional<ResultsFile> complete = checkOutputs(c, h)) return std::move(*complete);

  const fs::path partial = c.out.string() + ".partial.jsonl";
  FinishedMaps finished;
  finished.done = sweep_detail::loadPartial(partial, h, c.force, finished.engine_of,
                                            hasTwin(c) ? &finished.twin_done : nullptr);
  std::vector<const SweepItem*> todo;
  for (const auto& item : items)
    if (!finished.done.count(item.map_index)) todo.push_back(&item);
  if (!finished.done.empty() && !c.quiet)
    std::cerr << "resuming " << partial.string() << ": " << finished.done.size() << " of " << items.size()
              << " maps done before\n";
  if (c.out.has_parent_path()) fs::create_directories(c.out.parent_path());
  sweep_detail::PartialLog log(partial, h, finished.done.size());

  tbb::task_arena arena(c.threads > 0 ? c.threads : tbb::task_arena::automatic);
  const std::vector<MapToCount> maps = mapsToCount(todo, e);
  const SweepInputs inputs{c, findMethod(grid.method), grid.layout, data.scans, truths.counted(c.truth), truths.marked, hasTwin(c)};
  arena.execute([&] { engine->prepare(inputs, maps); });
  CountedMaps counted = countMaps(*engine, todo, maps, e, h, hasTwin(c), c.quiet, log, arena);

  ResultsFile f = finishSweep(h, finished, std::move(counted), engine->name());
  f.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  writeSweepResults(f, finished, c, log);
  return f;
}

}  // namespace occsweep
