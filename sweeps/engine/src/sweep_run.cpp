// A sweep: each selected map replayed from recorded events (default) or built directly (liboctomap for OctoMap,
// the k-NN mapper), then thresholded at every p_t.
#include <atomic>
#include <cerrno>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <tuple>
#include <mutex>
#include <set>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "occsweep/core/knn_inverse_sensor_model.hpp"
#include "occsweep/core/octomap_baseline.hpp"
#include "occsweep/eval/coordinates.hpp"
#include "occsweep/eval/dataset.hpp"
#include "occsweep/eval/bounded_read.hpp"
#include "occsweep/sweeps/progress.hpp"
#include "occsweep/sweeps/replay.hpp"
#include "occsweep/sweeps/sweep.hpp"
#include "occsweep/sweeps/version.hpp"
#include "sweep_internal.hpp"

namespace occsweep {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

using Clock = std::chrono::steady_clock;

}  // namespace

ResultsFile runSweep(const SweepConfig& c) {
  const auto start = Clock::now();
  const GridSpec grid = loadGrid(resolveGridPath(c.grid));
  const GridEnumeration e = enumerateGrid(grid);
  const std::vector<SweepItem> items = selectWork(grid, e, c.selection);
  if (c.engine != "replay" && c.engine != "direct") throw std::invalid_argument("engine must be replay or direct");
  const bool replaying = c.engine == "replay";
  Dataset data = readDataset(c.dataset);  // not const: replay frees the points once recorded
  requireInKeyRange(data, c.dataset, c.resolution);
  // Before anything is written: a region refused (past its limit, or holding no voxel) leaves no partial file.
  const GroundTruth full_truth = groundTruthOf(data, c.dataset, c.resolution);
  // Observable truth: the unobservable truth voxels leave the evaluation (docs/results-format.md, "Truth"). With a
  // twin (observable_out) they are marked and both truths are counted from the same maps.
  const bool twin = !c.observable_out.empty();
  if (twin && c.truth != TruthMode::Full) throw std::invalid_argument("sweep: observable_out needs full truth");
  const GroundTruth marked = evaluatedTruth(twin ? TruthMode::Observable : c.truth, full_truth, data.scans, c.s_c);
  const GroundTruth& truth = c.truth == TruthMode::Full ? full_truth : marked;

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
  h.truth = c.truth;
  ResultsHeader twin_header = h;
  twin_header.truth = TruthMode::Observable;

  // The same sweep's own file is resumed (or, complete, returned); anything else is refused unless --force, and
  // only occsweep's results are replaced even then (docs/robustness.md, "Outputs, temporaries and --force").
  std::error_code ec;
  if (fs::exists(fs::symlink_status(c.out, ec))) {
    checkOutputTarget(c.out, true, resultsOutput());
    ResultsFile old = readResults(c.out);
    std::string why;
    if (!sameWork(old.header, h, true, &why) && !c.force)
      throw std::runtime_error(c.out.string() + ": holds results of other work (" + why +
                               "); --force replaces it, or choose another --out");
    if (why.empty() && old.complete && (!twin || sweep_detail::completeResultsOf(c.observable_out, twin_header))) {
      fs::remove(c.out.string() + ".partial.jsonl", ec);  // superseded: a kill came between the rename and this
      return old;
    }
  }

  // The twin too replaces only occsweep's own results (a user's file there is refused before any work).
  if (twin && fs::exists(fs::symlink_status(c.observable_out, ec)))
    checkOutputTarget(c.observable_out, true, resultsOutput());
  const fs::path partial = c.out.string() + ".partial.jsonl";
  std::map<std::uint64_t, std::string> engine_of;  // provenance of every finished map
  std::map<std::uint64_t, MapResult> twin_done;
  std::map<std::uint64_t, MapResult> done =
      sweep_detail::loadPartial(partial, h, c.force, engine_of, twin ? &twin_done : nullptr);
  std::vector<const SweepItem*> todo;
  for (const auto& item : items)
    if (!done.count(item.map_index)) todo.push_back(&item);
  if (!done.empty() && !c.quiet)
    std::cerr << "resuming " << partial.string() << ": " << done.size() << " of " << items.size()
              << " maps done before\n";
  if (c.out.has_parent_path()) fs::create_directories(c.out.parent_path());
  std::ofstream log(partial, std::ios::app);
  // The log is what a killed sweep resumes from, so an error keeps it, unless it holds no finished map or a write
  // failed (a full disk): then it is removed rather than leave the disk full (docs/robustness.md).
  std::atomic<std::size_t> logged{done.size()};
  struct DropLog {
    const fs::path& file;
    const std::atomic<std::size_t>& maps;
    std::atomic<bool> write_failed{false};
    ~DropLog() {
      std::error_code ec;
      if (maps == 0 || write_failed) fs::remove(file, ec);
    }
  } drop_log{partial, logged};
  auto writeFailed = [&] {
    drop_log.write_failed = true;
    return OutputError(writeFailure(partial, errno));
  };
  if (done.empty()) {
    log.close();
    log.open(partial, std::ios::trunc);
    log << toJson(h).dump() << '\n' << std::flush;
  }
  if (!log) throw writeFailed();

  tbb::task_arena arena(c.threads > 0 ? c.threads : tbb::task_arena::automatic);
  const bool knn = grid.method == GridMethod::Knn;

  // Shared by every map: the events of the region voxels (replay), and for k-NN the distances of each k, which
  // depend only on the points, k and s_c.
  RecordedSet recorded;
  if (replaying) arena.execute([&] { recorded = recordSet(data.scans, marked, c.resolution, c.s_c); });
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

  std::vector<MapResult> fresh(todo.size()), twin_fresh(twin ? todo.size() : 0);
  std::mutex log_mutex;
  {
    Progress progress("sweep " + grid.name + " on " + data.name + " (" + c.engine + ")", todo.size(), c.quiet);
    arena.execute([&] {
      tbb::parallel_for(std::size_t(0), batches.size(), [&](std::size_t b) {
        const auto t0 = Clock::now();
        const std::vector<std::size_t>& batch = batches[b];
        std::vector<std::vector<ConfusionCounts>> counts, twin_counts;  // per map of the batch, per threshold
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
          // Without excluded voxels (full truth, no twin) both outputs are equal.
          counts = replayCounts(recorded, rules, p_t, &twin_counts);
          if (c.truth == TruthMode::Observable) counts.swap(twin_counts);
        } else {
          const SweepItem& item = *todo[batch[0]];
          const MapParams& m = e.maps[item.map_index];
          auto tree = knn ? KnnInverseSensorModel(knnParams(m, c, m.p_min)).buildMap(data.scans, distances.at(m.k))
                          : buildOctoMap(data.scans, octomapParams(m, c, m.p_min));
          std::vector<double> p_t;
          for (std::size_t t : item.thresholds) p_t.push_back(toDouble(e.thresholds[item.map_index][t]));
          counts.push_back(classify(sampleRegion(*tree, truth), p_t));
          if (twin) twin_counts.push_back(classify(sampleRegion(*tree, marked), p_t));
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
          json line = toJson(r, grid.method);
          line["engine"] = c.engine;  // provenance across resumes (docs/results-format.md)
          if (twin) {
            MapResult o = r;
            for (std::size_t t = 0; t < o.thresholds.size(); ++t) o.thresholds[t].counts = twin_counts[j][t];
            o.area = mapArea(o.thresholds);
            const json oj = toJson(o, grid.method);
            line[sweep_detail::kTwinField] = {{"thresholds", oj.at("thresholds")}, {"auc", oj.at("auc")}};
            twin_fresh[batch[j]] = std::move(o);
          }
          {
            std::lock_guard lock(log_mutex);
            log << line.dump() << '\n' << std::flush;
            if (!log) throw writeFailed();
            ++logged;
          }
          fresh[batch[j]] = std::move(r);
          progress.advance();
        }
      });
    });
  }
  for (auto& r : fresh) engine_of[r.map_index] = c.engine, done[r.map_index] = std::move(r);
  for (auto& r : twin_fresh) twin_done[r.map_index] = std::move(r);
  std::set<std::string> engines;
  for (const auto& [index, engine] : engine_of)
    if (done.count(index)) engines.insert(engine);
  if (engines.empty()) engines.insert(c.engine);
  h.engines.assign(engines.begin(), engines.end());
  h.engine = engines.size() == 1 ? *engines.begin() : "mixed";
  for (auto& [_, r] : done) f.maps.push_back(std::move(r));
  f.complete = true;
  f.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  try {
    if (twin) {  // first: a complete main file promises a complete twin
      ResultsFile o;
      o.header = h;
      o.header.truth = TruthMode::Observable;
      for (auto& [_, r] : twin_done) o.maps.push_back(std::move(r));
      o.complete = true;
      o.seconds = f.seconds;
      writeResults(o, c.observable_out);
    }
    writeResults(f, c.out);
  } catch (const OutputError&) {
    drop_log.write_failed = true;
    throw;
  }
  log.close();
  fs::remove(partial);
  return f;
}

}  // namespace occsweep
