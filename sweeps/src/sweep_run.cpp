// A sweep: each selected map replayed from recorded events (default) or built directly (liboctomap for OctoMap,
// the k-NN mapper), then thresholded at every p_t.
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <tuple>
#include <mutex>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "occsweep/core/knn_inverse_sensor_model.hpp"
#include "occsweep/core/octomap_baseline.hpp"
#include "occsweep/data/dataset.hpp"
#include "occsweep/data/import_bytes.hpp"
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
  if (fs::exists(fs::symlink_status(partial))) requireRegularFile(partial);  // a FIFO would block the sweep
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
  Dataset data = readDataset(c.dataset);  // not const: replay frees the points once recorded
  // Before anything is written: a region past its limit leaves no partial file (issue 13).
  const GroundTruth truth = groundTruthOf(data, c.dataset, c.resolution);

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
  if (!done.empty() && !c.quiet)
    std::cerr << "resuming " << partial.string() << ": " << done.size() << " of " << items.size()
              << " maps done before\n";
  if (c.out.has_parent_path()) fs::create_directories(c.out.parent_path());
  std::ofstream log(partial, std::ios::app);
  if (done.empty()) {
    log.close();
    log.open(partial, std::ios::trunc);
    log << toJson(h).dump() << '\n' << std::flush;
  }
  if (!log) throw std::runtime_error(partial.string() + ": cannot write");

  tbb::task_arena arena(c.threads > 0 ? c.threads : tbb::task_arena::automatic);
  const bool knn = grid.method == GridMethod::Knn;

  // Shared by every map: the events of the region voxels (replay), and for k-NN the distances of each k, which
  // depend only on the points, k and s_c.
  RecordedSet recorded;
  if (replaying) arena.execute([&] { recorded = recordSet(data.scans, truth, c.resolution, c.s_c); });
  std::map<int, KnnSetDistances> distances;
  std::map<int, std::vector<double>> cdf;
  if (knn) {
    for (const SweepItem* item : todo) distances[e.maps[item->map_index].k];
    std::vector<int> ks;
    for (auto& [k, _] : distances) ks.push_back(k);
    if (replaying) {
      // Replay needs only F(s) of the recorded hits: one k at a time, its distances freed at once (memory, issue 5).
      for (int k : ks) {
        arena.execute([&] { cdf[k] = hitCdf(recorded, parallelKnnDistances(data.scans, k, c.s_c), c.stats); });
        distances.erase(k);
      }
    } else {
      arena.execute([&] {
        tbb::parallel_for(std::size_t(0), ks.size(), [&](std::size_t i) {
          distances[ks[i]] = parallelKnnDistances(data.scans, ks[i], c.s_c);
        });
      });
    }
  }
  // Replay reads only the recorded events from here on: the points (12 bytes each) make room for its buffers.
  if (replaying) PointCloudSet().swap(data.scans);

  // Batches: with replay, up to kReplayLanes maps sharing their hit rule (k-NN: k, p_u, p_l) replayed together;
  // with direct, one map each.
  std::vector<std::vector<std::size_t>> batches;
  {
    std::map<std::tuple<int, Fixed, Fixed>, std::vector<std::size_t>> groups;
    for (std::size_t i = 0; i < todo.size(); ++i) {
      const MapParams& m = e.maps[todo[i]->map_index];
      groups[replaying ? std::make_tuple(m.k, m.p_u, m.p_l) : std::make_tuple(0, Fixed(i), Fixed(0))].push_back(i);
    }
    const std::size_t lanes = replaying ? kReplayLanes : 1;
    for (auto& [_, members] : groups)
      for (std::size_t b = 0; b < members.size(); b += lanes)
        batches.emplace_back(members.begin() + long(b), members.begin() + long(std::min(b + lanes, members.size())));
  }

  std::vector<MapResult> fresh(todo.size());
  std::mutex log_mutex;
  {
    Progress progress("sweep " + grid.name + " on " + data.name + " (" + c.engine + ")", todo.size(), c.quiet);
    arena.execute([&] {
      tbb::parallel_for(std::size_t(0), batches.size(), [&](std::size_t b) {
        const auto t0 = Clock::now();
        const std::vector<std::size_t>& batch = batches[b];
        std::vector<std::vector<ConfusionCounts>> counts;  // per map of the batch, per selected threshold
        if (replaying) {
          std::vector<float> hit_sums;
          const MapParams& first = e.maps[todo[batch[0]]->map_index];
          if (knn) hit_sums = knnHitSums(recorded, cdf.at(first.k), toDouble(first.p_u), toDouble(first.p_l));
          std::vector<ReplayRule> rules;
          std::vector<std::vector<double>> p_t;
          for (std::size_t i : batch) {
            const SweepItem& item = *todo[i];
            const MapParams& m = e.maps[item.map_index];
            rules.push_back(knn ? knnRule(m, hit_sums, c.variant) : octomapRule(m));
            p_t.emplace_back();
            for (std::size_t t : item.thresholds) p_t.back().push_back(toDouble(e.thresholds[item.map_index][t]));
          }
          counts = replayCounts(recorded, rules, p_t);
        } else {
          const SweepItem& item = *todo[batch[0]];
          const MapParams& m = e.maps[item.map_index];
          auto tree = knn ? KnnInverseSensorModel(knnParams(m, c, m.p_min)).buildMap(data.scans, distances.at(m.k))
                          : buildOctoMap(data.scans, octomapParams(m, c, m.p_min));
          const RegionSample sample = sampleRegion(*tree, truth);
          counts.emplace_back();
          for (std::size_t t : item.thresholds)
            counts.back().push_back(classify(sample, toDouble(e.thresholds[item.map_index][t])));
        }
        const double seconds = std::chrono::duration<double>(Clock::now() - t0).count() / double(batch.size());
        for (std::size_t j = 0; j < batch.size(); ++j) {
          const SweepItem& item = *todo[batch[j]];
          MapResult r;
          r.map_index = item.map_index;
          r.params = e.maps[item.map_index];
          for (std::size_t t = 0; t < item.thresholds.size(); ++t)
            r.thresholds.push_back({e.first_id[item.map_index] + item.thresholds[t],
                                    e.thresholds[item.map_index][item.thresholds[t]], counts[j][t]});
          r.area = mapArea(r.thresholds);
          r.seconds = seconds;  // a batch's time shared by its maps
          const std::string line = toJson(r, grid.method).dump();
          {
            std::lock_guard lock(log_mutex);
            log << line << '\n' << std::flush;
          }
          fresh[batch[j]] = std::move(r);
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
