// Results at scale, side by side in one run: a grid far finer than the paper's swept on the built-in
// scene into a results store and into JSON, then `results check` and `compare` on each: wall time, peak resident
// memory (VmHWM) and size on disk, and the ratios JSON / store. Build in Release (the default).
//   build/bench/bench_results                    the 3,202,220-combination grid (bench/grids/knn-fine-3m.json)
//   build/bench/bench_results --store-only       without the JSON runs (they need about 5 GB and 800 MB of disk)
//   build/bench/bench_results --grid bench/grids/knn-fine-30m.json --store-only    32.6 M combinations (7 min)
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include <sqlite3.h>
#include <tbb/version.h>

#include "bench_process.hpp"
#include "occsweep/eval/builtin_scene.hpp"
#include "occsweep/eval/dataset.hpp"

using namespace occsweep;
namespace fs = std::filesystem;

namespace {

struct Runs {
  bench::ProcessRun sweep, check, compare;
  double bytes = 0;
};

// The three commands a user runs on a results file of this grid, as they run them.
Runs measure(const fs::path& scene, const fs::path& grid, const fs::path& out) {
  fs::remove(out);
  const std::string limit = "4000000000";  // --max-combinations: the grid is the point
  Runs r;
  r.sweep = bench::runOccsweep({"sweep", "--dataset", scene.string(), "--grid", grid.string(), "--out", out.string(),
                                "--quiet", "--max-combinations", limit});
  r.bytes = double(fs::file_size(out));
  r.check = bench::runOccsweep({"results", "check", out.string(), "--max-combinations", limit});
  r.compare = bench::runOccsweep({"compare", out.string(), "--max-combinations", limit});
  return r;
}

void row(const char* what, const Runs& store, const Runs* json, const bench::ProcessRun Runs::*run) {
  const bench::ProcessRun& s = store.*run;
  std::printf("%-16s %10.2f s %10.0f MB", what, s.seconds, s.peak_bytes / 1e6);
  if (json) {
    const bench::ProcessRun& j = json->*run;
    std::printf(" %10.2f s %10.0f MB   %6.2f x %6.2f x", j.seconds, j.peak_bytes / 1e6, j.seconds / s.seconds,
                j.peak_bytes / s.peak_bytes);
  }
  std::printf("\n");
}

}  // namespace

int main(int argc, char** argv) {
  fs::path grid = occsweep::test::sourceTree() / "bench" / "grids" / "knn-fine-3m.json";
  // Its name (the file's stem) must be the grid's name for the lookup below.
  bool with_json = true;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--store-only")) with_json = false;
    else if (!std::strcmp(argv[i], "--grid") && i + 1 < argc) grid = argv[++i];
    else {
      std::fprintf(stderr, "usage: %s [--grid FILE] [--store-only]\n", argv[0]);
      return 2;
    }
  }
  // The grid found by name, as a user's grid folder: `results check` and `compare` then check every map against it.
  ::setenv("OCCSWEEP_GRIDS", grid.parent_path().c_str(), 1);
  const fs::path dir = occsweep::bench::scratchDir() / "results-scale";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path scene = dir / "scene";
  writeDataset(makeBuiltinScene(), scene);
  std::printf("bench_results: %s on the built-in scene; %s build, %u hardware threads, SQLite %s, oneTBB %d.%d\n",
              grid.filename().c_str(), OCCSWEEP_BUILD_TYPE, std::thread::hardware_concurrency(), sqlite3_libversion(),
              TBB_VERSION_MAJOR, TBB_VERSION_MINOR);
  std::fflush(stdout);
  const Runs store = measure(scene, grid, dir / "results.db");
  Runs json;
  if (with_json) json = measure(scene, grid, dir / "results.json");
  std::printf("\n%-16s %24s", "", "store (.db)");
  if (with_json) std::printf(" %24s   %16s", "JSON (before)", "JSON / store");
  std::printf("\n");
  row("sweep", store, with_json ? &json : nullptr, &Runs::sweep);
  row("results check", store, with_json ? &json : nullptr, &Runs::check);
  row("compare", store, with_json ? &json : nullptr, &Runs::compare);
  std::printf("%-16s %23.0f MB", "on disk", store.bytes / 1e6);
  if (with_json) std::printf(" %23.0f MB %20.2f x", json.bytes / 1e6, json.bytes / store.bytes);
  std::printf("\n\ngoals (the 3.2 M grid, docs/performance.md): sweep peak <= 500 MB, results <= 100 MB, compare <= 2 s and "
              "<= 300 MB\n");
  fs::remove_all(dir);
  return 0;
}
