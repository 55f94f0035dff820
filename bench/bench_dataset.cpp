// Generation's benchmark: one data set's 1,600 point cloud sets, generated each set alone (each set runs
// StereoSGBM::compute with its full parameters) and sharing the matcher across the 16 speckle variants of each
// matcher combination (docs/datasets.md, "How generation shares work"), side by side in one run, at ci and small
// scale, with the ratio; and whether the sets both paths made are byte-identical. Build in Release (the default).
//   build/bench/bench_dataset [--name building-voronoi-I] [--scales ci,small]
//                             [--before-sets ci=N,small=N] [--after-groups ci=N,small=N]
// Each path times an even subset and the time for all 1,600 is extrapolated linearly (sets are independent):
// "before" an even subset of the sets of the "after" groups, "after" an even subset of the 100 matcher
// combinations, whole (16 variants each: what shares one matcher). Rendering is timed once per run and counted
// once per data set on both sides.
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <sys/resource.h>
#include <tbb/version.h>

#include "occsweep/stereo/generate.hpp"
#include "occsweep/sweeps/grid.hpp"
#include "bench_process.hpp"

using namespace occsweep;
using namespace occsweep::stereo;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

struct BenchOptions {
  std::string name = "building-voronoi-I";
  std::vector<std::string> scales = {"ci", "small"};
  std::map<std::string, std::uint64_t> before_sets = {{"ci", 160}, {"small", 32}};
  std::map<std::string, std::uint64_t> after_groups = {{"ci", 100}, {"small", 10}};
};

std::vector<std::string> splitComma(const std::string& text) {
  std::vector<std::string> items;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) items.push_back(item);
  return items;
}

// "ci=160,small=32" onto `counts`.
void parseCounts(const std::string& text, std::map<std::string, std::uint64_t>& counts) {
  for (const std::string& item : splitComma(text)) {
    const auto eq = item.find('=');
    if (eq == std::string::npos) throw std::invalid_argument("expected SCALE=COUNT, got '" + item + "'");
    counts[item.substr(0, eq)] = std::stoull(item.substr(eq + 1));
  }
}

BenchOptions parseArguments(int argc, char** argv) {
  BenchOptions o;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--name")) o.name = argv[i + 1];
    else if (!std::strcmp(argv[i], "--scales")) o.scales = splitComma(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--before-sets")) parseCounts(argv[i + 1], o.before_sets);
    else if (!std::strcmp(argv[i], "--after-groups")) parseCounts(argv[i + 1], o.after_groups);
    else throw std::invalid_argument(std::string("unknown option ") + argv[i]);
  }
  return o;
}

// The grid's ids grouped by matcher combination (matcherParams), in id order.
std::vector<std::vector<std::uint64_t>> matcherGroupsOfGrid(const PointCloudGrid& grid) {
  std::vector<std::vector<std::uint64_t>> groups;
  std::vector<SgbmParams> keys;
  for (std::uint64_t id = 0; id < grid.size(); ++id) {
    const SgbmParams key = matcherParams(grid.at(id));
    const auto found = std::find(keys.begin(), keys.end(), key);
    if (found == keys.end()) keys.push_back(key), groups.push_back({id});
    else groups[std::size_t(found - keys.begin())].push_back(id);
  }
  return groups;
}

struct PathTiming {
  std::size_t sets = 0;
  double render_seconds = 0, set_seconds = 0;  ///< the run's rendering; its sets (wall time less rendering)
  double cpu_seconds = 0;                      ///< user + system time of the whole run, rendering included
};

// User + system time of this process so far, all threads.
double cpuSeconds() {
  rusage usage{};
  ::getrusage(RUSAGE_SELF, &usage);
  return double(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
         1e-6 * double(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

PathTiming timeGeneration(const DatasetName& name, GenerateConfig c, const PointCloudGrid& grid,
                          const std::vector<std::uint64_t>& ids, bool share_matcher, const fs::path& out) {
  c.pcs_ids = ids;
  c.share_matcher = share_matcher;
  fs::remove_all(out);
  const double cpu_start = cpuSeconds();
  const auto start = Clock::now();
  const DatasetSummary s = generateDataset(name, c, grid, out);
  const double wall = std::chrono::duration<double>(Clock::now() - start).count();
  return {ids.size(), s.render_seconds, wall - s.render_seconds, cpuSeconds() - cpu_start};
}

std::string bytesOf(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

// How many of the sets in `before` (pcs-* folders) have every file byte-identical in `after`.
std::pair<std::size_t, std::size_t> identicalSets(const fs::path& before, const fs::path& after) {
  std::size_t same = 0, compared = 0;
  for (const auto& set : fs::directory_iterator(before)) {
    if (!set.is_directory() || set.path().filename().string().rfind("pcs-", 0) != 0) continue;
    compared += 1;
    bool equal = true;
    for (const auto& f : fs::recursive_directory_iterator(set.path())) {
      if (!f.is_regular_file()) continue;
      const fs::path twin = after / fs::relative(f.path(), before);
      equal = equal && fs::exists(twin) && bytesOf(f.path()) == bytesOf(twin);
    }
    same += equal;
  }
  return {same, compared};
}

double peakResidentMegabytes() {
  rusage usage{};
  ::getrusage(RUSAGE_SELF, &usage);
  return double(usage.ru_maxrss) / 1024.0;
}

// CPU time of rendering the data set's keyframes once (both paths render them once per data set).
double renderCpuSeconds(const DatasetName& name, const GenerateConfig& c) {
  const Scene scene = makeScene(name, c.scene);
  const double start = cpuSeconds();
  (void)renderKeyframes(scene, zedLikeCamera(c.scale.width, c.scale.height), c, 1);
  return cpuSeconds() - start;
}

void benchScale(const BenchOptions& o, const std::string& scale, const PointCloudGrid& grid) {
  GenerateConfig c;
  c.scale = scaleConfig(scale);
  c.preview = false;
  c.progress = false;
  const auto groups = matcherGroupsOfGrid(grid);
  std::vector<std::uint64_t> after_ids;
  for (const std::uint64_t g : evenSubset(groups.size(), o.after_groups.at(scale)))
    after_ids.insert(after_ids.end(), groups[g].begin(), groups[g].end());
  std::vector<std::uint64_t> before_ids;
  for (const std::uint64_t i : evenSubset(after_ids.size(), o.before_sets.at(scale))) before_ids.push_back(after_ids[i]);

  const fs::path root = occsweep::bench::scratchDir() / "dataset-bench";
  const DatasetName name = parseDatasetName(o.name);
  const double render_cpu = renderCpuSeconds(name, c);
  const PathTiming before = timeGeneration(name, c, grid, before_ids, false, root / "before");
  const PathTiming after = timeGeneration(name, c, grid, after_ids, true, root / "after");
  const auto [same, compared] = identicalSets(root / "before" / o.name, root / "after" / o.name);
  fs::remove_all(root);

  // Per data set, all 1,600 sets: the timed sets scaled up, rendering once.
  const double all = double(grid.size());
  const double render = before.render_seconds;
  const double before_wall = render + before.set_seconds * all / double(before.sets);
  const double after_wall = render + after.set_seconds * all / double(after.sets);
  const double before_cpu = render_cpu + (before.cpu_seconds - render_cpu) * all / double(before.sets);
  const double after_cpu = render_cpu + (after.cpu_seconds - render_cpu) * all / double(after.sets);
  std::printf("%s scale (%dx%d, %d keyframes, %d disparities): timed %zu sets before, %zu after (%zu matcher "
              "combinations); byte-identical sets: %zu of %zu\n",
              scale.c_str(), c.scale.width, c.scale.height, c.scale.keyframes, c.scale.num_disparities, before.sets,
              after.sets, after.sets / 16, same, compared);
  std::printf("  %-34s %12s %12s %8s\n", "all 1,600 sets of one data set", "before", "after", "ratio");
  std::printf("  %-34s %11.1fs %11.1fs %8.3f  (1/%.1f)\n", "wall time, 2 threads", before_wall, after_wall,
              after_wall / before_wall, before_wall / after_wall);
  std::printf("  %-34s %11.1fs %11.1fs %8.3f  (1/%.1f)\n", "CPU time (user + system)", before_cpu, after_cpu,
              after_cpu / before_cpu, before_cpu / after_cpu);
  std::printf("  %-34s %11.1fs %11.1fs\n", "  of which rendering (wall, CPU)", render, render_cpu);
  std::fflush(stdout);
}

std::string loadAverage() {
  std::ifstream in("/proc/loadavg");
  std::string one, five;
  in >> one >> five;
  return one + " " + five;
}

}  // namespace

int main(int argc, char** argv) {
  const BenchOptions options = parseArguments(argc, argv);
  occsweep::addGridFolder(occsweep::bench::builtGrids());  // the build tree's copy of the grids (docs/install.md)
  const PointCloudGrid grid = loadPointCloudGrid(resolveGridPath("pointcloud"));
  std::printf("occsweep bench_dataset: build type %s, g++ %d.%d, OpenCV %s, oneTBB %d.%d, %u hardware threads, "
              "load average %s at start; data set %s, all %llu point cloud sets per scale (extrapolated from the "
              "timed subsets)\n",
              OCCSWEEP_BUILD_TYPE, __GNUC__, __GNUC_MINOR__, openCvVersion().c_str(), TBB_VERSION_MAJOR,
              TBB_VERSION_MINOR, std::thread::hardware_concurrency(), loadAverage().c_str(), options.name.c_str(),
              static_cast<unsigned long long>(grid.size()));
  std::fflush(stdout);
  for (const std::string& scale : options.scales) benchScale(options, scale, grid);
  std::printf("peak resident memory of this run: %.0f MB\n", peakResidentMegabytes());
  return 0;
}
