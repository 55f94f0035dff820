// Sweeps: each selected map of each grid counted by the sweep's engine (sweep_engine.hpp: replayed from events
// recorded once for every grid by default, or built directly), thresholded at every p_t, and written to the grid's
// output (sweep_outputs.cpp) as it is counted.
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <functional>
#include <iostream>
#include <optional>
#include <sstream>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "occsweep/core/method_registry.hpp"
#include "occsweep/eval/coordinates.hpp"
#include "occsweep/eval/dataset.hpp"
#include "occsweep/io/output_file.hpp"
#include "occsweep/eval/truth_coverage.hpp"
#include "occsweep/sweeps/progress.hpp"
#include "occsweep/sweeps/results_file.hpp"
#include "occsweep/sweeps/sweep.hpp"
#include "occsweep/sweeps/sweep_engine.hpp"
#include "occsweep/sweeps/version.hpp"
#include "sweep_internal.hpp"

namespace occsweep {
namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// The truths a sweep counts (docs/results-format.md, "Truth").
struct SweepTruths {
  GroundTruth full;
  GroundTruth marked;  // unobservable voxels in `excluded` under observable truth or with a twin; else full
  [[nodiscard]] const GroundTruth& counted(TruthMode mode) const { return mode == TruthMode::Full ? full : marked; }
};

bool hasTwin(const SweepConfig& c) { return !c.observable_out.empty(); }

// Observable truth: the unobservable truth voxels leave the evaluation. With a twin (observable_out) they are marked
// and both truths are counted from the same maps. Computed before anything is written: a region refused (past its
// limit, or holding no voxel) leaves no partial file.
SweepTruths sweepTruths(const SweepConfig& c, const Dataset& data) {
  SweepTruths t;
  t.full = groundTruthOf(data, c.dataset, c.map.resolution);
  const bool twin = hasTwin(c);
  if (twin && c.truth != TruthMode::Full) throw std::invalid_argument("sweep: observable_out needs full truth");
  t.marked = evaluatedTruth(twin ? TruthMode::Observable : c.truth, t.full, data.scans, c.map.s_c, c.dataset.string());
  return t;
}

// What the scans observe of the truth and how far their points lie from it, recorded with the results so that
// `sweep` and `compare` can warn (docs/import.md, "Truth coverage and alignment"); none without truth.
std::optional<TruthCoverage> coverageOf(const SweepTruths& truths, const Dataset& data, const SweepConfig& c) {
  if (truths.full.occupied.empty()) return std::nullopt;
  return measureTruthCoverage(truths.full, data.scans, c.map.s_c);
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
  h.map = c.map;
  h.engine = engine.name();
  h.truth = c.truth;
  return h;
}

// The selected maps not finished before, with the p_t values of their selected thresholds.
std::vector<MapToCount> mapsToCount(const std::vector<const SweepItem*>& todo, const GridEnumeration& e) {
  std::vector<MapToCount> maps;
  for (const SweepItem* item : todo) {
    MapToCount& m = maps.emplace_back();
    m.params = &e.map(item->map_index);
    for (std::size_t t : item->thresholds) m.p_t.push_back(toDouble(e.thresholdsOf(item->map_index)[t]));
  }
  return maps;
}

MapResult mapResult(const SweepItem& item, const GridEnumeration& e, const std::vector<ConfusionCounts>& counts,
                    double seconds) {
  MapResult r;
  r.map_index = item.map_index;
  r.params = e.map(item.map_index);
  r.thresholds.reserve(item.thresholds.size());  // sized once: no copy of a million thresholds while it grows
  for (std::size_t t = 0; t < item.thresholds.size(); ++t)
    r.thresholds.push_back({e.firstId(item.map_index) + item.thresholds[t],
                            e.thresholdsOf(item.map_index)[item.thresholds[t]], counts[t]});
  r.area = mapArea(r.thresholds);
  r.seconds = seconds;
  return r;
}

MapResult withCounts(MapResult r, const std::vector<ConfusionCounts>& counts) {
  for (std::size_t t = 0; t < r.thresholds.size(); ++t) r.thresholds[t].counts = counts[t];
  r.area = mapArea(r.thresholds);
  return r;
}

// One grid of a sweep: its selection, the header of its results, where they go, and the maps left to count.
struct GridSweep {
  const SweepConfig* config = nullptr;
  GridSpec grid;
  GridEnumeration e;
  std::vector<SweepItem> items;
  ResultsHeader header;
  std::unique_ptr<sweep_detail::GridOutput> output;
  std::vector<const SweepItem*> todo;
  std::vector<MapToCount> maps;
  double counting_seconds = 0.0;
};

// Several sweeps share one read and one recording only when they count the same data set the same way.
void requireOneDataSet(const std::vector<SweepConfig>& configs) {
  if (configs.empty()) throw std::invalid_argument("sweep: no grid");
  const SweepConfig& a = configs.front();
  for (const SweepConfig& b : configs)
    if (b.dataset != a.dataset || b.map != a.map || b.engine != a.engine || b.truth != a.truth ||
        b.threads != a.threads || b.observable_out.empty() != a.observable_out.empty())
      throw std::invalid_argument("sweep: grids swept together share the data set and every map setting");
}

// Every output refused now that would be refused once the data set is read (a user's file, two names of one file,
// a path whose `..` follows a link), so that a refusal costs no read, no truth and no recording. What a results file
// of the same work decides (resume, or other work) waits for the header, which needs the data set.
void refuseForeignOutputs(const std::vector<SweepConfig>& configs) {
  // Each output with the partial file it is written through (docs/results-format.md): two grids into one file
  // would lose the first's results, and one grid's output at another's partial name would be taken for it.
  std::vector<std::pair<std::string, fs::path>> outputs;
  for (std::size_t i = 0; i < configs.size(); ++i) {
    const SweepConfig& c = configs[i];
    const std::string flag = configs.size() == 1 ? "--out" : "--out " + std::to_string(i + 1);
    outputs.emplace_back(flag, c.out);
    outputs.emplace_back(flag + "'s partial file", partialOutputPath(c.out));
    if (!c.observable_out.empty()) outputs.emplace_back(flag + "'s observable-truth twin", c.observable_out);
  }
  requireSeparateOutputs(outputs);  // by entry, however spelt (docs/io.md, "Ownership")
  for (const SweepConfig& c : configs) {
    checkOutputTarget(c.out, true, resultsOutput());
    if (!c.observable_out.empty()) checkOutputTarget(c.observable_out, true, resultsOutput());
  }
}

// A shard is a block of whole maps: more shards than the selection has maps would leave some empty, and a file of
// no map is one `results check` refuses (docs/grids.md, "Sweep shards"). Refused before anything is written.
void refuseEmptyShards(const GridSpec& grid, const GridEnumeration& e, const SweepConfig& c) {
  const SweepSelection& s = c.selection;
  if (s.shard_count <= 1) return;
  SweepSelection unsharded = s;
  unsharded.shard_index = 0, unsharded.shard_count = 1;
  const std::uint64_t maps = s.group ? selectWork(grid, e, unsharded).size() : e.thresholded_maps;
  if (s.shard_count > maps)
    throw std::invalid_argument("--shard " + std::to_string(s.shard_index) + "/" + std::to_string(s.shard_count) +
                                ": " + std::to_string(s.shard_count) + " shards of grid " + grid.name + ", but its " +
                                (s.group ? "group holds " : "") + std::to_string(maps) + " maps (a shard is a block " +
                                "of whole maps): use at most " + std::to_string(maps) + " shards");
}

// The grid, its selection and the header of its results.
GridSweep openGrid(const SweepConfig& c, const Dataset& data, const SweepEngine& engine) {
  GridSweep g;
  g.config = &c;
  g.grid = loadGrid(resolveGridPath(c.grid));
  g.e = enumerateSelection(g.grid, c.selection);  // a shard's maps only: its memory is the shard's
  // A results file of no combination is one `results check` refuses: refused here, before anything is written.
  if (g.e.combinations == 0)
    throw std::invalid_argument(c.grid + ": grid " + g.grid.name + " has no combination (the relations between its "
                                "parameters leave none, docs/grids.md): nothing to sweep");
  refuseEmptyShards(g.grid, g.e, c);
  g.items = selectWork(g.grid, g.e, c.selection);
  g.header = sweepHeader(c, g.grid, g.e, data, engine);
  return g;
}

// A JSON file is built whole in memory (about 1.6 KB a combination): past this many, a store is the better output.
constexpr std::uint64_t kLargeForJson = 1'000'000;

std::uint64_t combinationsOf(const GridSweep& g) {
  std::uint64_t n = 0;
  for (const SweepItem& item : g.items) n += item.thresholds.size();
  return n;
}

// The grid's output, checked (the same work's complete results, other work, a user's file) and resumable.
void openOutput(GridSweep& g, const std::string& engine) {
  if (!isStorePath(g.config->out) && !g.config->quiet && combinationsOf(g) > kLargeForJson)
    std::cerr << "note: " << g.config->out.string() << ": " << combinationsOf(g) << " combinations into JSON, which is "
              << "built whole in memory; --out NAME.db writes a results store as the sweep runs "
                 "(docs/results-format.md, \"Results store\")\n";
  g.output = sweep_detail::makeGridOutput(*g.config, g.header, engine);
}

// The maps a grid has left; its partial output opened for them.
void beginCounting(GridSweep& g, const sweep_detail::RegionCounts& counted) {
  if (g.output->complete()) return;
  const std::vector<std::uint64_t> done = g.output->finished();
  if (!done.empty() && !g.config->quiet)
    std::cerr << "resuming " << g.output->partial().string() << ": " << done.size() << " of " << g.items.size()
              << " maps done before\n";
  for (const auto& item : g.items)
    if (!std::binary_search(done.begin(), done.end(), item.map_index)) g.todo.push_back(&item);
  g.maps = mapsToCount(g.todo, g.e);
  g.output->begin(g.todo.size(), counted);
}

// Records the events once for every grid with work (replay) or readies the direct builds.
void prepareEngine(SweepEngine& engine, const SweepConfig& c, Dataset& data, const SweepTruths& truths,
                   std::vector<GridSweep>& grids, std::vector<std::size_t>& slot, tbb::task_arena& arena) {
  std::vector<GridMaps> work;
  for (GridSweep& g : grids) {
    slot.push_back(work.size());
    if (!g.output->complete()) work.push_back({&findMethod(g.grid.method), &g.grid.layout, &g.maps});
  }
  if (work.empty()) return;
  const SweepInputs inputs{c, data.scans, truths.counted(c.truth), truths.marked, hasTwin(c)};
  arena.execute([&] { engine.prepare(inputs, work); });
}

// Counts every map of one grid, its batches in parallel, each batch handed to the grid's output as it finishes.
void countGrid(const SweepEngine& engine, std::size_t slot, GridSweep& g, tbb::task_arena& arena) {
  const auto start = Clock::now();
  const std::vector<std::vector<std::size_t>> batches = engine.batches(slot);
  const bool twin = hasTwin(*g.config);
  Progress progress("sweep " + g.header.grid_name + " on " + g.header.dataset_name + " (" + engine.name() + ")",
                    g.todo.size(), g.config->quiet, "maps");
  arena.execute([&] {
    tbb::parallel_for(std::size_t(0), batches.size(), [&](std::size_t b) {
      const auto t0 = Clock::now();
      const std::vector<std::size_t>& batch = batches[b];
      const BatchCounts counts = engine.count(slot, batch);
      const double seconds = secondsSince(t0) / double(batch.size());  // a batch's time shared by its maps
      std::vector<MapResult> results, twins;
      for (std::size_t j = 0; j < batch.size(); ++j) {
        results.push_back(mapResult(*g.todo[batch[j]], g.e, counts.counts[j], seconds));
        if (twin) twins.push_back(withCounts(results.back(), counts.observable[j]));
      }
      g.output->add(std::move(results), std::move(twins), batch);
      for (std::size_t j = 0; j < batch.size(); ++j) progress.advance();
    });
  });
  g.counting_seconds = secondsSince(start);
}

// What one grid's sweep wrote: its results (JSON: whole; a store: its header) and the summary.
struct GridOutcome {
  ResultsFile file;
  SweepSummary summary;
};

std::string metres(double value) {
  std::ostringstream text;
  text << value << " m";
  return text.str();
}

std::vector<GridOutcome> runGrids(const std::vector<SweepConfig>& configs) {
  const auto start = Clock::now();
  requireOneDataSet(configs);
  refuseForeignOutputs(configs);
  const SweepConfig& c = configs.front();
  const std::unique_ptr<SweepEngine> engine = makeSweepEngine(c.engine);
  announcePhase("reading data set " + c.dataset.string(), c.quiet);
  Dataset data = readDataset(c.dataset);  // not const: replay frees the points once recorded
  requireInKeyRange(data, c.dataset, c.map.resolution);
  announcePhase("ground truth of " + data.name + "'s region at resolution " + metres(c.map.resolution), c.quiet);
  const SweepTruths truths = sweepTruths(c, data);  // before anything is written: a refused region leaves nothing
  std::vector<GridSweep> grids;  // never grown after this loop: outputs and the engine keep pointers into it
  grids.reserve(configs.size());
  const std::optional<TruthCoverage> coverage = coverageOf(truths, data, c);
  for (const SweepConfig& config : configs) {
    grids.push_back(openGrid(config, data, *engine));
    grids.back().header.coverage = coverage;
  }
  for (GridSweep& g : grids) openOutput(g, engine->name());  // every output checked before any is written
  const GroundTruth& counted = truths.counted(c.truth);
  for (GridSweep& g : grids) beginCounting(g, {counted.evaluatedVoxelCount(), counted.evaluatedTrueVoxelCount()});

  tbb::task_arena arena(c.threads > 0 ? c.threads : tbb::task_arena::automatic);
  std::vector<std::size_t> slot;
  announcePhase("preparing the " + engine->name() + " engine: " + std::to_string(data.scans.size()) + " scans for " +
                    std::to_string(grids.size()) + (grids.size() == 1 ? " grid" : " grids"), c.quiet);
  prepareEngine(*engine, c, data, truths, grids, slot, arena);
  const double shared_seconds = secondsSince(start);  // reading, truth and recording: every grid's
  std::vector<GridOutcome> out;
  for (std::size_t i = 0; i < grids.size(); ++i) {
    GridSweep& g = grids[i];
    if (!g.output->complete()) countGrid(*engine, slot[i], g, arena);
    ResultsFile f = g.output->complete() ? *g.output->complete() : g.output->finish(shared_seconds + g.counting_seconds);
    const SweepSummary summary{f.header, g.items.size(), combinationsOf(g), f.seconds};
    out.push_back({std::move(f), summary});
  }
  return out;
}

}  // namespace

std::vector<SweepSummary> sweepGrids(const std::vector<SweepConfig>& configs) {
  std::vector<SweepSummary> out;
  for (GridOutcome& g : runGrids(configs)) out.push_back(std::move(g.summary));
  return out;
}

SweepSummary sweepToFile(const SweepConfig& c) { return sweepGrids({c}).front(); }

ResultsFile runSweep(const SweepConfig& c) {
  ResultsFile f = std::move(runGrids({c}).front().file);
  return isStorePath(c.out) ? readResults(c.out) : f;
}

}  // namespace occsweep
