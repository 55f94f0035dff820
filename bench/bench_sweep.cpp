// The sweep benchmark: on a paper-scale point cloud set, side by side in one run, one liboctomap build, the k-NN
// mapper's direct build, the event recording, the replay of knn-opt and octomap-opt, their ratios, the run-time
// models (Eq. 17, 18) and the sweep's peak memory; and the k-NN search both ways, the
// nanoflann k-d tree against the grid of cells, on the same clouds. Build in Release (the default). The times the
// ratios are made of are each the least of three runs, alternated round by round.
//   build/bench/bench_sweep                  the paper-scale set: building-voronoi-I's median point cloud set at
//                                            paper scale (144 keyframes, 2.9 M points), generated once by
//                                            `occsweep dataset generate` (about 5 min) into build/bench/paper-set
//   build/bench/bench_sweep --builtin [--scans 120 --width 200 --height 160]   the dense built-in range scene
//   build/bench/bench_sweep --dataset DIR    any data set
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <sys/resource.h>

#include <thread>
#include <vector>

#include <octomap/octomap.h>
#include <tbb/parallel_for.h>
#include <tbb/version.h>

#include "bench_process.hpp"
#include "occsweep/methods/knn/knn_average_distance.hpp"
#include "occsweep/methods/builtin_methods.hpp"
#include "occsweep/methods/knn/knn_inverse_sensor_model.hpp"
#include "occsweep/methods/knn/knn_method.hpp"
#include "occsweep/methods/octomap/octomap_baseline.hpp"
#include "occsweep/eval/builtin_scene.hpp"
#include "occsweep/eval/dataset.hpp"
#include "occsweep/stats/runtime_model.hpp"
#include "occsweep/sweeps/replay.hpp"
#include "occsweep/sweeps/sweep.hpp"
#include "occsweep/sweeps/sweep_engine.hpp"
#include "occsweep/sweeps/tbb_scan_executor.hpp"
#include "occsweep/core/method_registry.hpp"

using namespace occsweep;
using Clock = std::chrono::steady_clock;

namespace {

using bench::seconds;

// Peak resident memory of one occsweep process as a user runs it, in bytes (bench_process.hpp).
double peakBytes(const std::vector<std::string>& args) { return bench::runOccsweep(args).peak_bytes; }

double sweepPeakBytes(const std::string& dataset, const std::string& grid, const std::string& out) {
  std::filesystem::remove(out);
  return peakBytes({"sweep", "--dataset", dataset, "--grid", grid, "--out", out, "--quiet"});
}

// The default set: what the paper maps (a stereo camera's clouds, voxel-filtered at 0.1 m, about 140 keyframes),
// deterministic from the generator's seed. Generated on first use and kept beside this program.
std::string paperScaleSet() {
  const std::filesystem::path out = occsweep::bench::scratchDir() / "paper-set";
  const std::filesystem::path set = out / "building-voronoi-I" / "pcs-0800";
  if (!std::filesystem::exists(set / "manifest.json")) {
    std::printf("generating the paper-scale set once (about 5 minutes on 2 cores) into %s\n", out.c_str());
    std::fflush(stdout);
    const std::vector<std::string> args = {"dataset", "generate", "--name", "building-voronoi-I", "--scale", "paper",
                                           "--pcs", "800", "--no-preview", "--out", out.string()};
    (void)peakBytes(args);
  }
  return set.string();
}

PointCloudSet firstScans(const PointCloudSet& set, std::size_t n) { return {set.begin(), set.begin() + long(n)}; }

constexpr double kResolution = 0.1, kSC = 4.0;

struct BenchOptions {
  BuiltinSceneConfig config;
  std::string dataset_dir;  ///< empty: the built-in scene
  bool builtin = false;
};

BenchOptions parseArguments(int argc, char** argv) {
  BenchOptions o;
  o.config.scans = 120;
  o.config.width = 200;
  o.config.height = 160;
  for (int i = 1; i < argc; ++i)
    if (!std::strcmp(argv[i], "--builtin")) o.builtin = true;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--builtin")) --i;  // a flag: the pairs start one later
    else if (!std::strcmp(argv[i], "--dataset")) o.dataset_dir = argv[i + 1];
    if (!std::strcmp(argv[i], "--scans")) o.config.scans = std::atoi(argv[i + 1]);
    if (!std::strcmp(argv[i], "--width")) o.config.width = std::atoi(argv[i + 1]);
    if (!std::strcmp(argv[i], "--height")) o.config.height = std::atoi(argv[i + 1]);
  }
  return o;
}

// The set: built in, given, or (neither) the paper-scale set.
Dataset loadSet(BenchOptions& o) {
  if (!o.builtin && o.dataset_dir.empty()) o.dataset_dir = paperScaleSet();
  const Dataset data = o.dataset_dir.empty() ? makeBuiltinScene(o.config) : readDataset(o.dataset_dir);
  const std::size_t n = pointCount(data.scans);
  if (o.dataset_dir.empty())
    std::printf("set: built-in scene, %zu scans of %dx%d rays, %zu points (%.1f MB as float32)\n", data.scans.size(),
                o.config.width, o.config.height, n, double(n) * 12 / 1e6);
  else
    std::printf("set: %s, %zu scans, %zu points (%.1f MB as float32)\n", o.dataset_dir.c_str(), data.scans.size(), n,
                double(n) * 12 / 1e6);
  return data;
}

// The whole comparison as `occsweep sweep` runs it (reading the set, recording, replay, writing results), once
// on one thread for a like-for-like ratio and once on all cores.
struct SweepSeconds {
  double knn_1, om_1, knn_all, om_all;
  double both_1, both_all;  ///< both grids in one process, one read and one recording (sweepGrids)
};

SweepConfig sweepConfig(const std::filesystem::path& dir, const char* grid, int threads) {
  SweepConfig c;
  c.dataset = dir / "set";
  c.grid = grid;
  c.out = dir / (std::string(grid) + std::to_string(threads) + ".json");
  c.threads = threads;
  c.quiet = true;
  std::filesystem::remove(c.out);
  return c;
}

double sweepSeconds(const std::filesystem::path& dir, const char* grid, int threads) {
  const SweepConfig c = sweepConfig(dir, grid, threads);
  return seconds([&] { (void)runSweep(c); });
}

double bothSweepsSeconds(const std::filesystem::path& dir, int threads) {
  const std::vector<SweepConfig> both = {sweepConfig(dir, "knn-opt", threads), sweepConfig(dir, "octomap-opt", threads)};
  return seconds([&] { (void)sweepGrids(both); });
}

SweepSeconds timeSweeps(const std::filesystem::path& dir) {
  SweepSeconds s{};
  s.knn_1 = sweepSeconds(dir, "knn-opt", 1), s.om_1 = sweepSeconds(dir, "octomap-opt", 1);
  s.both_1 = bothSweepsSeconds(dir, 1);
  s.knn_all = sweepSeconds(dir, "knn-opt", 0), s.om_all = sweepSeconds(dir, "octomap-opt", 0);
  s.both_all = bothSweepsSeconds(dir, 0);
  return s;
}

void keepLeast(SweepSeconds& least, const SweepSeconds& s) {
  least.knn_1 = std::min(least.knn_1, s.knn_1), least.om_1 = std::min(least.om_1, s.om_1);
  least.both_1 = std::min(least.both_1, s.both_1);
  least.knn_all = std::min(least.knn_all, s.knn_all), least.om_all = std::min(least.om_all, s.om_all);
  least.both_all = std::min(least.both_all, s.both_all);
}

// One grid replayed by the sweep's own engine, on all cores: what its maps share (recording, features), then
// every batch; throughput counts the batches only, the part that grows with the grid.
struct ReplaySeconds {
  std::string grid, method;
  double prepare, replay;
  std::size_t combinations;
};

ReplaySeconds timeReplay(const Dataset& data, const GroundTruth& truth, const char* name) {
  const GridSpec grid = loadGrid(resolveGridPath(name));
  const GridEnumeration e = enumerateGrid(grid);
  std::vector<MapToCount> maps;
  std::size_t combos = 0;
  for (std::size_t m = 0; m < e.maps.size(); ++m) {
    maps.push_back({&e.maps[m], {}});
    for (Fixed t : e.thresholds[m]) maps.back().p_t.push_back(toDouble(t)), ++combos;
  }
  SweepConfig config;
  config.map.resolution = kResolution, config.map.s_c = kSC;
  PointCloudSet scans = data.scans;  // the engine frees its copy
  const SweepInputs inputs{config, scans, truth, truth, false};
  const auto engine = makeSweepEngine("replay");
  const double prepare = seconds([&] { engine->prepare(inputs, {{&findMethod(grid.method), &grid.layout, &maps}}); });
  const auto batches = engine->batches(0);
  const double replay = seconds([&] {
    tbb::parallel_for(std::size_t(0), batches.size(), [&](std::size_t b) { (void)engine->count(0, batches[b]); });
  });
  return {name, grid.method, prepare, replay, combos};
}

// The sweep's parts, on all cores.
struct PartSeconds {
  double record, distances;
  unsigned long long scan_voxel_updates;
  std::vector<ReplaySeconds> replays;  ///< one per shipped grid: every method's throughput
};

PartSeconds timeParts(const Dataset& data, const GroundTruth& truth) {
  PartSeconds s{};
  RecordedSet recorded;
  s.record = seconds([&] { recorded = recordSet(data.scans, truth, kResolution, kSC); });
  s.distances = seconds([&] { (void)computeKnnDistances(data.scans, 1, kSC, tbbScanExecutor()); });
  s.scan_voxel_updates = recorded.scan_voxel_updates;
  for (const char* grid : {"knn-opt", "octomap-opt", "sor-octomap-opt", "ror-octomap-opt", "range-octomap-opt"})
    s.replays.push_back(timeReplay(data, truth, grid));
  return s;
}

// The k-NN search alone, 1 thread, on every scan's z_in: the former k-d tree and the grid of cells on the same
// clouds, and how many s_i differ in any bit (docs/performance.md: only float-ranking ties can make them).
struct SearchSeconds {
  int k;
  double kd_tree, grid;
  std::size_t points, differing;
};

SearchSeconds timeSearches(const PointCloudSet& scans, int k) {
  SearchSeconds s{k, 0, 0, 0, 0};
  for (const Scan& scan : scans) {
    std::vector<octomap::point3d> inner;
    for (std::uint32_t i : innerPoints(scan, kSC)) inner.push_back(scan.points[i]);
    std::vector<double> tree, grid;
    s.kd_tree += seconds([&] { tree = averageKnnDistancesKdTree(inner, k); });
    s.grid += seconds([&] { grid = averageKnnDistances(inner, k); });
    s.points += inner.size();
    for (std::size_t i = 0; i < tree.size(); ++i) s.differing += std::memcmp(&tree[i], &grid[i], sizeof(double)) != 0;
  }
  return s;
}

void printSearches(const PointCloudSet& scans) {
  std::printf("\n%-44s %10s %10s %10s %16s\n", "k-NN search, every scan's z_in, 1 thread", "k-d tree s", "grid s",
              "grid / kd", "s_i differing");
  for (int k : {1, 5, 10}) {
    const SearchSeconds s = timeSearches(scans, k);
    std::printf("%-44s %10.3f %10.3f %10.3f %9zu of %zu\n", ("k = " + std::to_string(k)).c_str(), s.kd_tree, s.grid,
                s.grid / s.kd_tree, s.differing, s.points);
  }
}

// Per method: its replay throughput and its ratio to k-NN's (docs/methods.md: a method swept within 2x of k-NN).
void printReplayThroughput(const std::vector<ReplaySeconds>& replays) {
  std::printf("\n%-20s %-14s %12s %12s %12s %16s %10s\n", "grid", "method", "combinations", "prepare s", "replay s",
              "combinations/s", "/ k-NN");
  const double knn_rate = double(replays.front().combinations) / replays.front().replay;
  for (const ReplaySeconds& r : replays) {
    const double rate = double(r.combinations) / r.replay;
    std::printf("%-20s %-14s %12zu %12.3f %12.3f %16.0f %10.3f\n", r.grid.c_str(), r.method.c_str(), r.combinations,
                r.prepare, r.replay, rate, rate / knn_rate);
  }
}

// The direct build on 1 thread, and on all cores as `occsweep map` runs it: the scans' k-NN searches and their
// rays' events in parallel, applied in scan order (buildMap on a TBB ScanExecutor: the same map).
struct DirectSeconds {
  double one_thread, all_cores;
};

DirectSeconds timeDirectBuilds(const PointCloudSet& scans, const KnnParams& knn) {
  const KnnInverseSensorModel model(knn);
  DirectSeconds d{};
  d.one_thread = seconds([&] { (void)model.buildMap(scans); });
  d.all_cores = seconds([&] {
    const ScanExecutor tbb = tbbScanExecutor();
    (void)model.buildMap(scans, computeKnnDistances(scans, knn.k, knn.map.s_c, tbb), tbb);
  });
  return d;
}

// The times the ratios are made of, each the least of kRounds runs, the steps alternated round by round: on a
// noisy machine one slow run of either side no longer moves a ratio (one liboctomap build of the built-in scene
// took 3.0 to 4.1 s within an hour on 2 vCPU; docs/performance.md, "How to measure").
constexpr int kRounds = 3;
struct RatioSeconds {
  double octomap = std::numeric_limits<double>::infinity();
  DirectSeconds knn{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  SweepSeconds sweep{};
};

RatioSeconds timeRounds(const PointCloudSet& scans, const OctoMapParams& om, const KnnParams& knn,
                        const std::filesystem::path& dir) {
  RatioSeconds least;
  for (int round = 0; round < kRounds; ++round) {
    least.octomap = std::min(least.octomap, seconds([&] { (void)buildOctoMap(scans, om); }));
    const DirectSeconds d = timeDirectBuilds(scans, knn);
    least.knn.one_thread = std::min(least.knn.one_thread, d.one_thread);
    least.knn.all_cores = std::min(least.knn.all_cores, d.all_cores);
    const SweepSeconds s = timeSweeps(dir);
    if (round == 0) least.sweep = s;
    else keepLeast(least.sweep, s);
  }
  return least;
}

void printSteps(double t_octomap, const DirectSeconds& t_knn, const SweepSeconds& sweep, const PartSeconds& parts) {
  std::printf("\n%-52s %10s\n", ("step (the least of " + std::to_string(kRounds) + " alternated runs)").c_str(),
              "seconds");
  std::printf("%-52s %10.3f\n", "liboctomap build (insertPointCloud per scan, 1 thread)", t_octomap);
  std::printf("%-52s %10.3f / %.3f\n", "k-NN mapper direct build (k = 1, incl. k-NN; 1 thread / all cores)",
              t_knn.one_thread, t_knn.all_cores);
  std::printf("%-52s %10.3f / %.3f\n", "occsweep sweep knn-opt (1 thread / all cores)", sweep.knn_1, sweep.knn_all);
  std::printf("%-52s %10.3f / %.3f\n", "occsweep sweep octomap-opt (1 thread / all cores)", sweep.om_1, sweep.om_all);
  std::printf("  parts, all cores: recording %.3f s (%llu region voxel updates), k-NN distances %.3f s\n",
              parts.record, parts.scan_voxel_updates, parts.distances);
  printReplayThroughput(parts.replays);
  std::printf("%-52s %10.3f / %.3f\n", "occsweep sweep --grid knn-opt --grid octomap-opt (1 / all)", sweep.both_1,
              sweep.both_all);
  std::printf("\n(a) knn-opt + octomap-opt sweeps (recording included) / one liboctomap build:\n"
              "    in one process, one recording: %.3f on 1 thread, %.3f on all cores   (goal <= 0.5 paper set, <= 1.0 "
              "built-in)\n    as two sweeps:                  %.3f on 1 thread, %.3f on all cores\n",
              sweep.both_1 / t_octomap, sweep.both_all / t_octomap, (sweep.knn_1 + sweep.om_1) / t_octomap,
              (sweep.knn_all + sweep.om_all) / t_octomap);
  std::printf("(b) k-NN direct build / one liboctomap build:                 %.3f on 1 thread, %.3f on all cores   "
              "(goal <= 0.7)\n", t_knn.one_thread / t_octomap, t_knn.all_cores / t_octomap);
  const ReplaySeconds& knn = parts.replays[0];
  const ReplaySeconds& om = parts.replays[1];
  std::printf("(c) replay throughput: %.0f combinations/s (all cores, knn-opt and octomap-opt)\n",
              double(knn.combinations + om.combinations) / (knn.replay + om.replay));
}

// Growth with points (and k): Eq. 17 for liboctomap and for the whole sweep, Eq. 18 for the k-NN build.
void printGrowthFits(const Dataset& data, const GroundTruth& truth, const OctoMapParams& om, const KnnParams& knn) {
  std::vector<RuntimeSample> s_om, s_knn, s_sweep;
  for (std::size_t scans : {data.scans.size() / 4, data.scans.size() / 2, 3 * data.scans.size() / 4, data.scans.size()}) {
    const PointCloudSet part = firstScans(data.scans, scans);
    const double np = double(pointCount(part));
    s_om.push_back({np, 0, seconds([&] { (void)buildOctoMap(part, om); })});
    for (int k : {1, 3, 5, 7}) {
      KnnParams p = knn;
      p.k = k;
      s_knn.push_back({np, double(k), seconds([&] { (void)KnnInverseSensorModel(p).buildMap(part); })});
    }
    s_sweep.push_back({np, 0, seconds([&] {
                         (void)recordSet(part, truth, kResolution, kSC);
                         (void)KnnCdfFeature(1, {.s_c = kSC}).compute(part, tbbScanExecutor());
                       })});
  }
  const RuntimeFit f_om = fitEq17(s_om), f_knn = fitEq18(s_knn), f_sweep = fitEq17(s_sweep);
  std::printf("\nEq. 17 liboctomap:     t = %.4e N + %.4e          R^2 = %.4f\n", f_om.a, f_om.b, f_om.r_squared);
  std::printf("Eq. 18 k-NN direct:    t = (%.4e k + %.4e) N + %.4e   R^2 = %.4f\n", f_knn.a, f_knn.b, f_knn.c, f_knn.r_squared);
  std::printf("Eq. 17 recording+k-NN:  t = %.4e N + %.4e          R^2 = %.4f\n", f_sweep.a, f_sweep.b, f_sweep.r_squared);
}

void printPeakMemory(const std::filesystem::path& dir, std::size_t points) {
  const double points_bytes = double(points) * 12;
  const double peak_knn = sweepPeakBytes((dir / "set").string(), "knn-opt", (dir / "knn.json").string());
  const double peak_om = sweepPeakBytes((dir / "set").string(), "octomap-opt", (dir / "om.json").string());
  std::printf("\npeak memory of `occsweep sweep` (whole process): knn-opt %.1f MB, octomap-opt %.1f MB\n", peak_knn / 1e6,
              peak_om / 1e6);
  // The binary alone (code of occsweep, liboctomap, TBB, OpenCV and their libraries, loaded and touched) is
  // resident before any data is read: `occsweep grid count` reads a small grid file and nothing else.
  const double binary = peakBytes({"grid", "count", "knn-opt"});
  std::printf("peak / points in memory (%.1f MB): knn-opt %.2f, octomap-opt %.2f   (goal <= 3)\n", points_bytes / 1e6,
              peak_knn / points_bytes, peak_om / points_bytes);
  std::printf("the binary alone (`occsweep grid count`): %.1f MB; peak minus it / points: knn-opt %.2f, octomap-opt "
              "%.2f\n", binary / 1e6, (peak_knn - binary) / points_bytes, (peak_om - binary) / points_bytes);
}

// The machine: /proc/cpuinfo's model name.
std::string cpuModel() {
  std::ifstream in("/proc/cpuinfo");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown CPU";
}

}  // namespace

int main(int argc, char** argv) {
  BenchOptions options = parseArguments(argc, argv);
  occsweep::registerBuiltinMethods();
  occsweep::addGridFolder(occsweep::bench::builtGrids());  // the build tree's copy of the grids (docs/install.md)
  std::printf("occsweep bench_sweep: build type %s, g++ %d.%d, liboctomap %s, oneTBB %d.%d, nanoflann %x.%x.%x, "
              "%u hardware threads, %s\n",
              OCCSWEEP_BUILD_TYPE, __GNUC__, __GNUC_MINOR__, OCCSWEEP_OCTOMAP_VERSION, TBB_VERSION_MAJOR, TBB_VERSION_MINOR,
              NANOFLANN_VERSION >> 8, (NANOFLANN_VERSION >> 4) & 0xf, NANOFLANN_VERSION & 0xf,
              std::thread::hardware_concurrency(), cpuModel().c_str());
  const Dataset data = loadSet(options);
  const auto dir = std::filesystem::temp_directory_path() / ("occsweep-bench-" + std::to_string(::getpid()));
  writeDataset(data, dir / "set");

  OctoMapParams om;
  KnnParams knn;
  knn.k = 1;  // knn-opt's k
  const RatioSeconds t = timeRounds(data.scans, om, knn, dir);
  const GroundTruth truth = makeGroundTruth(data.truth, data.region, kResolution);
  printSteps(t.octomap, t.knn, t.sweep, timeParts(data, truth));
  printSearches(data.scans);
  printGrowthFits(data, truth, om, knn);
  printPeakMemory(dir, pointCount(data.scans));
  std::filesystem::remove_all(dir);
  return 0;
}
