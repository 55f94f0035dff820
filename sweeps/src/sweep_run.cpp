// The direct sweep engine: build each selected map (liboctomap for OctoMap), threshold it at every p_t.
#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "occsweep/core/knn_inverse_sensor_model.hpp"
#include "occsweep/core/octomap_baseline.hpp"
#include "occsweep/data/dataset.hpp"
#include "occsweep/sweeps/progress.hpp"
#include "occsweep/sweeps/sweep.hpp"
#include "occsweep/sweeps/version.hpp"

namespace occsweep {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

using Clock = std::chrono::steady_clock;

// Finished maps of an interrupted run: OUT.partial.jsonl, a header line then one map per line. A line cut by
// a kill is ignored (its map is simply done again).
std::map<std::uint64_t, MapResult> loadPartial(const fs::path& partial, const ResultsHeader& header) {
  std::map<std::uint64_t, MapResult> done;
  std::ifstream in(partial);
  std::string line;
  if (!std::getline(in, line)) return done;
  ResultsHeader old;
  try {
    old = parseHeader(json::parse(line), partial.string());
  } catch (const std::exception&) {
    return done;  // header cut short: nothing finished yet
  }
  std::string why;
  if (!sameWork(old, header, true, &why))
    throw std::runtime_error(partial.string() + ": an interrupted sweep of other work (" + why +
                             "); remove it or choose another --out");
  while (std::getline(in, line)) {
    try {
      MapResult m = parseMapResult(json::parse(line), header.method, partial.string(), "line");
      done[m.map_index] = std::move(m);
    } catch (const std::exception&) {
    }
  }
  return done;
}

}  // namespace

ResultsFile runSweep(const SweepConfig& c) {
  const auto start = Clock::now();
  const GridSpec grid = loadGrid(resolveGridPath(c.grid));
  const GridEnumeration e = enumerateGrid(grid);
  const std::vector<SweepItem> items = selectWork(grid, e, c.selection);
  const Dataset data = readDataset(c.dataset);

  ResultsFile f;
  ResultsHeader& h = f.header;
  h.version = kVersion;
  h.commit = kGitCommit;
  h.grid_name = grid.name;
  h.grid_hash = grid.file_hash;
  h.method = grid.method;
  h.grid_combinations = e.combinations;
  h.selection = c.selection;
  h.dataset_name = data.name;
  h.dataset_hash = datasetContentHash(c.dataset);
  h.point_cloud_set = data.source;
  h.resolution = c.resolution;
  h.s_c = c.s_c;
  h.variant = c.variant == UpdateVariant::Literal ? "literal" : "default";
  h.stats = c.stats == StatsMode::Online ? "online" : "batch";

  if (fs::exists(c.out)) {
    ResultsFile old = readResults(c.out);
    std::string why;
    if (!sameWork(old.header, h, true, &why))
      throw std::runtime_error(c.out.string() + ": holds results of other work (" + why +
                               "); remove it or choose another --out");
    if (old.complete) return old;
  }

  const fs::path partial = c.out.string() + ".partial.jsonl";
  std::map<std::uint64_t, MapResult> done = loadPartial(partial, h);
  std::vector<const SweepItem*> todo;
  for (const auto& item : items)
    if (!done.count(item.map_index)) todo.push_back(&item);
  if (c.out.has_parent_path()) fs::create_directories(c.out.parent_path());
  std::ofstream log(partial, std::ios::app);
  if (done.empty()) {
    log.close();
    log.open(partial, std::ios::trunc);
    log << toJson(h).dump() << '\n' << std::flush;
  }
  if (!log) throw std::runtime_error(partial.string() + ": cannot write");

  const GroundTruth truth = makeGroundTruth(data.truth, data.region, c.resolution);
  tbb::task_arena arena(c.threads > 0 ? c.threads : tbb::task_arena::automatic);

  // k-NN: the distances depend only on the points, k and s_c: once per k for every map that uses it.
  std::map<int, KnnSetDistances> distances;
  if (grid.method == GridMethod::Knn) {
    for (const SweepItem* item : todo) distances[e.maps[item->map_index].k];
    std::vector<int> ks;
    for (auto& [k, _] : distances) ks.push_back(k);
    arena.execute([&] {
      tbb::parallel_for(std::size_t(0), ks.size(), [&](std::size_t i) {
        distances[ks[i]] = computeKnnDistances(data.scans, ks[i], c.s_c);
      });
    });
  }

  std::vector<MapResult> fresh(todo.size());
  std::mutex log_mutex;
  {
    Progress progress("sweep " + grid.name + " on " + data.name, todo.size(), c.quiet);
    arena.execute([&] {
      tbb::parallel_for(std::size_t(0), todo.size(), [&](std::size_t i) {
        const auto t0 = Clock::now();
        const SweepItem& item = *todo[i];
        const MapParams& m = e.maps[item.map_index];
        const auto& p_t = e.thresholds[item.map_index];
        auto tree = grid.method == GridMethod::Knn
                        ? KnnInverseSensorModel(knnParams(m, c, m.p_min)).buildMap(data.scans, distances.at(m.k))
                        : buildOctoMap(data.scans, octomapParams(m, c, m.p_min));
        const RegionSample sample = sampleRegion(*tree, truth);
        MapResult r;
        r.map_index = item.map_index;
        r.params = m;
        for (std::size_t t : item.thresholds)
          r.thresholds.push_back({e.first_id[item.map_index] + t, p_t[t], classify(sample, toDouble(p_t[t]))});
        r.area = mapArea(r.thresholds);
        r.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
        const std::string line = toJson(r, grid.method).dump();
        {
          std::lock_guard lock(log_mutex);
          log << line << '\n' << std::flush;
        }
        fresh[i] = std::move(r);
        progress.advance();
      });
    });
  }
  for (auto& r : fresh) done[r.map_index] = std::move(r);
  for (auto& [_, r] : done) f.maps.push_back(std::move(r));
  f.complete = true;
  f.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  writeResults(f, c.out);
  log.close();
  fs::remove(partial);
  return f;
}

}  // namespace occsweep
