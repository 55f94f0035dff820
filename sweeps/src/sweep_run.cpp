// A sweep: each selected map replayed from recorded events (default) or built directly (liboctomap for OctoMap,
// the k-NN mapper), then thresholded at every p_t.
#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <tuple>
#include <mutex>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "occsweep/core/knn_inverse_sensor_model.hpp"
#include "occsweep/core/octomap_baseline.hpp"
#include "occsweep/data/dataset.hpp"
#include "occsweep/sweeps/progress.hpp"
#include "occsweep/sweeps/replay.hpp"
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
  if (c.engine != "replay" && c.engine != "direct") throw std::invalid_argument("engine must be replay or direct");
  const bool replaying = c.engine == "replay";
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
  h.engine = c.engine;

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
  const bool knn = grid.method == GridMethod::Knn;

  // Shared by every map: the events of the region voxels (replay), and for k-NN the distances of each k, which
  // depend only on the points, k and s_c.
  RecordedSet recorded;
  if (replaying) recorded = recordSet(data.scans, truth, c.resolution, c.s_c);
  std::map<int, KnnSetDistances> distances;
  std::map<int, std::vector<double>> cdf;
  if (knn) {
    for (const SweepItem* item : todo) distances[e.maps[item->map_index].k];
    std::vector<int> ks;
    for (auto& [k, _] : distances) ks.push_back(k);
    arena.execute([&] {
      tbb::parallel_for(std::size_t(0), ks.size(), [&](std::size_t i) {
        distances[ks[i]] = computeKnnDistances(data.scans, ks[i], c.s_c);
      });
    });
    if (replaying)
      for (int k : ks) cdf[k] = hitCdf(recorded, distances.at(k), c.stats);
  }

  // Batches of maps sharing k, p_u and p_l: with replay their hit sums are computed once.
  std::vector<std::vector<std::size_t>> batches;
  {
    std::map<std::tuple<int, Fixed, Fixed>, std::size_t> batch_of;
    for (std::size_t i = 0; i < todo.size(); ++i) {
      const MapParams& m = e.maps[todo[i]->map_index];
      const auto key = replaying && knn ? std::make_tuple(m.k, m.p_u, m.p_l) : std::make_tuple(0, Fixed(i), Fixed(0));
      auto [it, fresh] = batch_of.try_emplace(key, batches.size());
      if (fresh) batches.emplace_back();
      batches[it->second].push_back(i);
    }
  }

  std::vector<MapResult> fresh(todo.size());
  std::mutex log_mutex;
  {
    Progress progress("sweep " + grid.name + " on " + data.name + " (" + c.engine + ")", todo.size(), c.quiet);
    arena.execute([&] {
      tbb::parallel_for(std::size_t(0), batches.size(), [&](std::size_t b) {
        std::vector<float> hit_sums;
        for (std::size_t i : batches[b]) {
          const auto t0 = Clock::now();
          const SweepItem& item = *todo[i];
          const MapParams& m = e.maps[item.map_index];
          const auto& p_t = e.thresholds[item.map_index];
          RegionSample sample;
          if (replaying) {
            if (knn && hit_sums.empty()) hit_sums = knnHitSums(recorded, cdf.at(m.k), toDouble(m.p_u), toDouble(m.p_l));
            sample = replay(recorded, knn ? knnRule(m, hit_sums, c.variant) : octomapRule(m));
          } else {
            auto tree = knn ? KnnInverseSensorModel(knnParams(m, c, m.p_min)).buildMap(data.scans, distances.at(m.k))
                            : buildOctoMap(data.scans, octomapParams(m, c, m.p_min));
            sample = sampleRegion(*tree, truth);
          }
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
        }
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
