// The replay engine against the direct engine (liboctomap for OctoMap, the k-NN mapper), every combination of
// octomap-opt and knn-opt: identical confusion counts, no tolerance. The built-in scene itself is covered by
// test_golden (golden files made by the direct engine, recomputed by replay).
#include <catch2/catch.hpp>

#include "occsweep/eval/builtin_scene.hpp"
#include "occsweep/sweeps/sweep.hpp"
#include "test_helpers.hpp"

using namespace occsweep;
namespace fs = std::filesystem;

namespace {

ResultsFile run(const fs::path& data, const std::string& grid, const std::string& engine, const fs::path& out,
                UpdateVariant variant = UpdateVariant::Default, StatsMode stats = StatsMode::Batch,
                const SweepSelection& selection = {}) {
  SweepConfig c;
  c.selection = selection;
  c.dataset = data;
  c.grid = grid;
  c.engine = engine;
  c.out = out;
  c.map.variant = variant;
  c.map.stats = stats;
  c.quiet = true;
  return runSweep(c);
}

void requireSame(const ResultsFile& direct, const ResultsFile& replayed) {
  const auto diffs = resultDifferences(direct, replayed);
  for (std::size_t i = 0; i < std::min<std::size_t>(diffs.size(), 10); ++i) UNSCOPED_INFO(diffs[i]);
  REQUIRE(diffs.empty());
}

}  // namespace

TEST_CASE("replay equals direct for every combination of both grids on 5 random scenes") {
  const auto dir = test::scratch("replay-seeds");
  for (std::uint64_t seed = 11; seed <= 15; ++seed) {
    SplitMix64 rng(seed);
    BuiltinSceneConfig config;
    config.seed = seed;
    config.scans = 4 + int(rng.below(6));
    config.width = 24 + int(rng.below(24));
    config.height = 18 + int(rng.below(18));
    config.orbit_radius = 1.8 + 2.0 * rng.uniform();  // sometimes beyond s_c's reach of the far side
    config.outlier_fraction = 0.1 * rng.uniform();
    const auto data = dir / ("scene" + std::to_string(seed));
    writeDataset(makeBuiltinScene(config), data);
    INFO("seed " << seed);
    for (const char* grid : {"octomap-opt", "knn-opt"}) {
      INFO(grid);
      const std::string tag = std::to_string(seed) + grid;
      requireSame(run(data, grid, "direct", dir / (tag + "-direct.json")),
                  run(data, grid, "replay", dir / (tag + "-replay.json")));
    }
  }
}

TEST_CASE("replay equals direct for the literal variant and online statistics") {
  // Each scene sweeps a third of knn-opt (shard 1, 2 or 3 of 3), so that every combination is compared in every
  // mode once over the three scenes: the whole grid on every scene took 814 s of CI's sanitizer run.
  const auto dir = test::scratch("replay-variants");
  for (std::uint64_t seed = 21; seed <= 23; ++seed) {
    SweepSelection third;
    third.shard_index = seed - 21, third.shard_count = 3;
    const auto data = dir / ("scene" + std::to_string(seed));
    writeDataset(makeBuiltinScene({.seed = seed, .scans = 6, .width = 32, .height = 24, .outlier_fraction = 0.08}), data);
    for (auto variant : {UpdateVariant::Default, UpdateVariant::Literal})
      for (auto stats : {StatsMode::Batch, StatsMode::Online}) {
        const std::string tag = std::to_string(seed) + (variant == UpdateVariant::Literal ? "-literal" : "-default") +
                                (stats == StatsMode::Online ? "-online" : "-batch");
        INFO(tag);
        const ResultsFile direct = run(data, "knn-opt", "direct", dir / (tag + "-direct.json"), variant, stats, third);
        REQUIRE(direct.maps.size() == 150);  // a third of knn-opt's 450 maps
        requireSame(direct, run(data, "knn-opt", "replay", dir / (tag + "-replay.json"), variant, stats, third));
      }
  }
}

TEST_CASE("replay distinguishes what it should: a different variant gives different counts") {
  const auto dir = test::scratch("replay-sensitive");
  const auto data = dir / "scene";
  writeDataset(makeBuiltinScene({.seed = 5, .scans = 6, .width = 32, .height = 24}), data);
  const auto a = run(data, "knn-opt", "replay", dir / "default.json");
  const auto b = run(data, "knn-opt", "replay", dir / "literal.json", UpdateVariant::Literal);
  std::size_t differing = 0;
  for (std::size_t m = 0; m < a.maps.size(); ++m)
    for (std::size_t t = 0; t < a.maps[m].thresholds.size(); ++t)
      differing += !(a.maps[m].thresholds[t].counts == b.maps[m].thresholds[t].counts);
  CHECK(differing > 100);
}
