// The golden results in results/builtin/ are recomputed and must match, as `occsweep results diff` checks them
// (diffResults): every TP/FP/FN/TN and every AUC exactly (tolerance 0, within 1e-12 a fortiori). Regenerate them with
// tools/regenerate_golden.sh only when a change is intended.
#include <catch2/catch.hpp>

#include "occsweep/core/method_registry.hpp"
#include "occsweep/methods/octomap/octomap_baseline.hpp"
#include "occsweep/eval/builtin_scene.hpp"
#include "occsweep/sweeps/results_diff.hpp"
#include "occsweep/sweeps/sweep.hpp"
#include "test_helpers.hpp"

using namespace occsweep;
namespace fs = std::filesystem;

namespace {

const fs::path kGolden = occsweep::test::sourceTree() / "results" / "builtin";

fs::path builtinScene(const std::string& test_name) {
  const auto dir = test::scratch(test_name) / "scene";  // one folder per test: ctest runs them in parallel
  writeDataset(makeBuiltinScene(), dir);  // the default settings, as tools/regenerate_golden.sh
  return dir;
}

// Sweeps `grid` on the scene with `engine` and requires exactly the golden file's numbers (diffResults at AUC
// tolerance 0: any TP/FP/FN/TN, any AUC, a missing combination).
void requireGolden(const fs::path& scene, const std::string& grid, const std::string& engine) {
  INFO("grid " << grid << ", engine " << engine);
  const ResultsFile golden = readResults(kGolden / (grid + ".json"));
  REQUIRE(golden.complete);
  // A different scene would make every number differ: say so plainly.
  REQUIRE(datasetContentHash(scene) == golden.header.dataset_hash);
  SweepConfig c;
  c.dataset = scene;
  c.grid = grid;
  c.engine = engine;
  c.out = scene.parent_path() / (grid + "-" + engine + ".json");
  c.quiet = true;
  const ResultsFile fresh = runSweep(c);
  CHECK(fresh.header.engine == engine);
  const ResultsDiff diff = diffResults(golden, fresh, 0.0);
  for (const auto& d : diff.header) UNSCOPED_INFO(d.field << ": " << d.candidate << ", golden " << d.golden);
  for (std::size_t i = 0; i < std::min<std::size_t>(diff.combinations.size(), 10); ++i) {
    const ResultsDifference& d = diff.combinations[i];
    UNSCOPED_INFO("map " << *d.map_index << " (" << d.combination << "): " << d.field << " " << d.candidate
                         << ", golden " << d.golden);
  }
  CHECK(diff.empty());
}

}  // namespace

TEST_CASE("golden results of the built-in scene recompute identically") {
  const auto scene = builtinScene("golden-recompute");
  for (const char* grid : {"octomap-opt", "knn-opt"}) requireGolden(scene, grid, "replay");  // the default engine
}

TEST_CASE("the direct engine (liboctomap for OctoMap, one k-NN map per combination) reproduces the golden results") {
  // The golden files are recomputed above by the replay engine; here by the reference engine, map by map, so that
  // replay and direct are compared on the built-in scene for every combination of both grids (docs/performance.md,
  // "Correctness first").
  const auto scene = builtinScene("golden-direct");
  for (const char* grid : {"octomap-opt", "knn-opt"}) requireGolden(scene, grid, "direct");
}

TEST_CASE("the golden check fails when a single voxel's classification changes") {
  const auto scene = builtinScene("golden-perturb");
  const ResultsFile golden = readResults(kGolden / "octomap-opt.json");
  const Dataset data = readDataset(scene);
  const GroundTruth truth = makeGroundTruth(data.truth, data.region, golden.header.map.resolution);
  const MapResult& m = golden.maps.at(7);
  const SweepConfig c;
  MethodValues values;
  for (Fixed v : m.params.values) values.push_back(toDouble(v));
  auto tree = findMethod("octomap").buildMap(data.scans, values, {c.map, {}, {}});
  RegionSample sample = sampleRegion(*tree, truth);

  auto withCounts = [&](const RegionSample& s) {
    ResultsFile f = golden;
    MapResult& changed = f.maps.at(7);
    for (auto& t : changed.thresholds) t.counts = classify(s, toDouble(t.p_t));
    changed.area = mapArea(changed.thresholds);
    return f;
  };
  // Unchanged, the recomputed map agrees with the golden file...
  REQUIRE(diffResults(golden, withCounts(sample), 0.0).empty());
  // ...and one truly occupied voxel that the map knew and called occupied becomes unknown: a TP turns FN.
  REQUIRE_FALSE(sample.positive_log_odds.empty());
  sample.positive_log_odds.pop_back();  // sorted: the most confident one, occupied at every p_t
  const ResultsDiff diff = diffResults(golden, withCounts(sample), 0.0);
  REQUIRE_FALSE(diff.empty());
  CHECK(diff.header.empty());
  std::size_t tp_rows = 0;
  for (const auto& d : diff.combinations) {
    CHECK(d.map_index == 7u);  // map 7 alone, named
    tp_rows += d.field == "tp";
  }
  CHECK(tp_rows == golden.maps.at(7).thresholds.size());  // occupied at every p_t: a TP less at each
}
