// Every registered method swept by the replay engine equals its direct build (liboctomap for OctoMap and its
// filters, the k-NN mapper, the rule through OcTree::updateNode for the rest), for every combination of its grid on
// random scenes; the filters switched off are plain OctoMap voxel for voxel; a method registered from outside the
// library is swept like the shipped ones (docs/methods.md).
#include <catch2/catch.hpp>

#include "occsweep/core/method_registry.hpp"
#include "occsweep/methods/knn/knn_method.hpp"
#include "occsweep/methods/outlier_filters/outlier_filter_methods.hpp"
#include "occsweep/methods/range_octomap/range_octomap_method.hpp"
#include "occsweep/eval/builtin_scene.hpp"
#include "occsweep/eval/ground_truth.hpp"
#include "occsweep/sweeps/replay.hpp"
#include "occsweep/sweeps/results_diff.hpp"
#include "occsweep/sweeps/sweep.hpp"
#include "occsweep/sweeps/tbb_scan_executor.hpp"
#include "test_helpers.hpp"

using namespace occsweep;
namespace fs = std::filesystem;

namespace {

ResultsFile run(const fs::path& data, const std::string& grid, const std::string& engine, const fs::path& out) {
  SweepConfig c;
  c.dataset = data;
  c.grid = grid;
  c.engine = engine;
  c.out = out;
  c.quiet = true;
  return runSweep(c);
}

void requireSameCounts(const ResultsFile& direct, const ResultsFile& replayed) {
  const ResultsDiff diff = diffResults(direct, replayed, 0.0, CountsCheck::Exact);
  for (std::size_t i = 0; i < std::min<std::size_t>(diff.combinations.size(), 10); ++i)
    UNSCOPED_INFO(diff.combinations[i].combination << " " << diff.combinations[i].field << ": "
                                                   << diff.combinations[i].golden << " / "
                                                   << diff.combinations[i].candidate);
  REQUIRE(diff.header.empty());
  REQUIRE(diff.combinations.empty());
}

// Scenes with outliers, so that the filters remove points and rays.
fs::path randomScene(const fs::path& dir, std::uint64_t seed) {
  SplitMix64 rng(seed);
  BuiltinSceneConfig config;
  config.seed = seed;
  config.scans = 4 + int(rng.below(5));
  config.width = 24 + int(rng.below(20));
  config.height = 18 + int(rng.below(14));
  config.orbit_radius = 1.8 + 2.0 * rng.uniform();
  config.outlier_fraction = 0.05 + 0.15 * rng.uniform();
  const fs::path data = dir / ("scene" + std::to_string(seed));
  writeDataset(makeBuiltinScene(config), data);
  return data;
}

std::vector<std::pair<octomap::OcTreeKey, float>> leaves(const octomap::OcTree& tree) {
  std::vector<std::pair<octomap::OcTreeKey, float>> out;
  for (auto it = tree.begin_leafs(); it != tree.end_leafs(); ++it) out.emplace_back(it.getKey(), it->getLogOdds());
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) {
    return std::tie(a.first[0], a.first[1], a.first[2]) < std::tie(b.first[0], b.first[1], b.first[2]);
  });
  return out;
}

// A method of the test's own, registered from outside the library: every in-range point adds l(p_near) when within
// r_split of the sensor and l(p_far) beyond (a PointSum over the Range feature), built directly by the default
// buildMapByRule.
class SplitRangeMethod final : public MappingMethod {
 public:
  std::string name() const override { return "test-split-range"; }
  std::string description() const override { return "test: near points count p_near, far points p_far"; }
  std::string reference() const override { return "tests/sweeps/test_methods.cpp"; }
  std::vector<MethodParameter> parameters() const override {
    return {{"r_split", "r_s", "near/far split, metres", 2.0, 0, 100, true, false, false, "test"},
            {"p_near", "p_n", "near point's probability", 0.7, 0.5, 1, false, true, false, "test"},
            {"p_far", "p_f", "far point's probability", 0.55, 0.5, 1, false, true, false, "test"},
            {"p_max", "p_max", "upper clamp", 0.97, 0.5, 1, false, true, false, "Eq. 12"},
            {"p_min", "p_min", "lower clamp", 0.12, 0, 0.5, true, true, false, "Eq. 12"},
            {"p_m", "p_m", "miss", 0.4, 0, 0.5, true, true, false, "Eq. 12"}};
  }
  std::vector<ParameterRelation> relations() const override { return {{"p_near", "p_far", false, "test"}}; }
  std::vector<std::string> sharedByLanes() const override { return {"r_split", "p_near", "p_far"}; }
  MapRule rule(const MethodValues& v, const RuleContext& c) const override {
    MapRule rule;
    rule.l_min = logOdds(parameterValue(*this, v, "p_min"));
    rule.l_max = logOdds(parameterValue(*this, v, "p_max"));
    rule.update = {logOdds(parameterValue(*this, v, "p_m")), logOdds(parameterValue(*this, v, "p_m")), c.map.variant};
    rule.hit.kind = HitRule::Kind::PointSum;
    rule.hit.feature = std::make_shared<RangeFeature>();
    const float near = logOdds(parameterValue(*this, v, "p_near")), far = logOdds(parameterValue(*this, v, "p_far"));
    const double split = parameterValue(*this, v, "r_split");
    rule.hit.pointLogOdds = [=](double r) { return r <= split ? near : far; };
    return rule;
  }
};

}  // namespace

TEST_CASE("every registered method: replay equals direct for every combination of its grid on 5 random scenes") {
  const auto dir = test::processScratch("methods-seeds");
  for (std::uint64_t seed = 31; seed <= 35; ++seed) {
    const fs::path data = randomScene(dir, seed);
    INFO("seed " << seed);
    for (const auto& method : registeredMethods()) {
      if (method->name().starts_with("test-")) continue;  // the test's own method: its own case below
      const std::string grid = method->name() + "-opt";
      INFO(grid);
      const std::string tag = std::to_string(seed) + grid;
      requireSameCounts(run(data, grid, "direct", dir / (tag + "-direct.json")),
                        run(data, grid, "replay", dir / (tag + "-replay.json")));
    }
  }
}

TEST_CASE("the filters remove points on the test scenes, so their replay is exercised") {
  const auto dir = test::processScratch("methods-removal");
  std::size_t points = 0, sor_kept = 0, ror_kept = 0;
  for (std::uint64_t seed = 31; seed <= 35; ++seed)
    for (const Scan& scan : readDataset(randomScene(dir, seed)).scans) {
      points += scan.points.size();
      sor_kept += statisticalOutlierRemoval(scan.points, 10, 0.5).size();
      ror_kept += radiusOutlierRemoval(scan.points, 0.1, 5).size();
    }
  INFO(points << " points, SOR keeps " << sor_kept << ", ROR keeps " << ror_kept);
  CHECK(sor_kept < points);
  CHECK(ror_kept < points);
  CHECK(sor_kept > points / 2);  // a filter, not an eraser
}

TEST_CASE("switched off, sor-octomap and ror-octomap are plain OctoMap voxel for voxel, built and replayed") {
  const auto dir = test::processScratch("methods-off");
  const fs::path data = randomScene(dir, 41);
  const Dataset d = readDataset(data);
  const MapContext context{};  // the paper's settings: 0.1 m voxels, s_c 4 m, default variant, batch statistics
  const MethodValues octomap{0.97, 0.12, 0.7, 0.4};
  const auto plain = leaves(*findMethod("octomap").buildMap(d.scans, octomap, context));
  REQUIRE(plain.size() > 1000);
  MethodValues sor{10, 1e6}, ror{0.2, 0};
  sor.insert(sor.end(), octomap.begin(), octomap.end());
  ror.insert(ror.end(), octomap.begin(), octomap.end());
  CHECK(leaves(*findMethod("sor-octomap").buildMap(d.scans, sor, context)) == plain);
  CHECK(leaves(*findMethod("ror-octomap").buildMap(d.scans, ror, context)) == plain);
  // And replayed: grids of octomap-opt's combinations with the filter off count exactly what octomap-opt counts.
  const ResultsFile om = run(data, "octomap-opt", "replay", dir / "octomap.json");
  const std::string inner = R"("p_max": {"value": 0.98}, "p_min": {"value": 0.02}, "p_h": {"min": 0.50, "max": 0.98, "step": 0.12},
    "p_m": {"min": 0.02, "max": 0.38, "step": 0.12}, "p_t": {"step": 0.12})";
  for (const auto& [method, filter] : {std::pair{"sor-octomap", R"("k": [10], "std_mul": {"value": 1000000})"},
                                       std::pair{"ror-octomap", R"("radius": {"value": 0.2}, "min_neighbors": [0])"}}) {
    const fs::path grid = dir / (std::string(method) + "-off.json");
    std::ofstream(grid) << R"({"name": "off", "method": ")" << method << R"(", "parameters": {)" << filter << ", "
                        << inner << "}}";
    const ResultsFile off = run(data, grid.string(), "replay", dir / (std::string(method) + "-off-results.json"));
    REQUIRE(off.maps.size() == om.maps.size());
    for (std::size_t m = 0; m < om.maps.size(); ++m)
      for (std::size_t t = 0; t < om.maps[m].thresholds.size(); ++t)
        CHECK(off.maps[m].thresholds[t].counts == om.maps[m].thresholds[t].counts);
  }
}

TEST_CASE("a method registered from outside the library sweeps by replay as its rule builds directly") {
  registerMethod(std::make_shared<SplitRangeMethod>());
  CHECK_THROWS_WITH(registerMethod(std::make_shared<SplitRangeMethod>()), Catch::Contains("registered already"));
  CHECK(findMethod("test-split-range").name() == "test-split-range");
  const auto dir = test::processScratch("methods-own");
  const fs::path grid = dir / "split.json";
  std::ofstream(grid) << R"({"name": "split", "method": "test-split-range", "parameters": {
    "r_split": {"min": 1.5, "max": 3.0, "step": 0.75}, "p_near": {"min": 0.6, "max": 0.9, "step": 0.15},
    "p_far": {"min": 0.51, "max": 0.81, "step": 0.15}, "p_max": {"value": 0.97}, "p_min": {"value": 0.12},
    "p_m": {"min": 0.2, "max": 0.45, "step": 0.125}, "p_t": {"step": 0.1}}})";
  for (std::uint64_t seed = 51; seed <= 55; ++seed) {
    INFO("seed " << seed);
    const fs::path data = randomScene(dir, seed);
    const ResultsFile direct = run(data, grid.string(), "direct", dir / ("direct" + std::to_string(seed) + ".json"));
    CHECK(direct.maps.size() > 20);
    requireSameCounts(direct, run(data, grid.string(), "replay", dir / ("replay" + std::to_string(seed) + ".json")));
  }
}

TEST_CASE("features are shared by identity: its arguments and mode are part of it, equal ones computed once") {
  const FeatureIdentity knn3 = KnnCdfFeature(3, {}).identity();
  CHECK(knn3 == KnnCdfFeature(3, {}).identity());
  CHECK(knn3 != KnnCdfFeature(4, {}).identity());
  CHECK(knn3 != KnnCdfFeature(3, {.stats = StatsMode::Online}).identity());
  CHECK(knn3 != KnnCdfFeature(3, {.s_c = 5.0}).identity());
  CHECK(knn3 != SorScoreFeature(3).identity());
  CHECK(RorNeighboursFeature(0.2).identity() != RorNeighboursFeature(0.3).identity());
  FeatureCache cache;
  int made = 0;
  const auto make = [&] { return ++made; };
  const int& first = cache.get<int>(knn3, make);
  CHECK(&cache.get<int>(KnnCdfFeature(3, {}).identity(), make) == &first);
  CHECK(made == 1);
  CHECK(cache.get<int>(SorScoreFeature(3).identity(), make) == 2);
  CHECK_THROWS_WITH(cache.get<double>(knn3, [] { return 1.0; }), Catch::Contains("kept as another type"));
}

TEST_CASE("a feature at the recorded hits equals its value at every point, read there (k-NN's shortcut too)") {
  const MapSettings map;  // 0.1 m voxels, s_c 4 m
  for (std::uint64_t seed = 51; seed <= 53; ++seed) {
    BuiltinSceneConfig config;
    config.seed = seed;
    config.scans = 5;
    config.outlier_fraction = 0.1;
    const Dataset d = makeBuiltinScene(config);
    const GroundTruth truth = makeGroundTruth(d.truth, d.region, map.resolution);
    const RecordedSet r = recordSet(d.scans, truth, map.resolution, map.s_c);
    REQUIRE(r.hit_scan.size() > 100);
    const HitPoints hits{r.hit_scan, r.hit_inner, map.s_c};
    const auto check = [&](const PointFeature& f) {
      INFO("seed " << seed << ", " << f.identity().name << " " << f.identity().mode);
      const std::vector<double> at_hits = f.valuesAtHits(d.scans, hits, tbbScanExecutor());
      const std::vector<double> read = f.PointFeature::valuesAtHits(d.scans, hits, {});  // compute(), read at the hits
      REQUIRE(at_hits.size() == r.hit_scan.size());
      CHECK(at_hits == read);
      CHECK(std::none_of(at_hits.begin(), at_hits.end(), [](double v) { return std::isnan(v); }));
    };
    for (int k : {1, 3, 7})
      for (StatsMode stats : {StatsMode::Batch, StatsMode::Online})
        check(KnnCdfFeature(k, {.s_c = map.s_c, .stats = stats}));
    check(RangeFeature());
    check(SorScoreFeature(5));
    check(RorNeighboursFeature(0.2));
  }
}

TEST_CASE("the registry refuses a method that breaks its rules, naming the rule") {
  class Broken final : public MappingMethod {
   public:
    std::string name_ = "broken";
    std::vector<MethodParameter> params_ = {{"p_max", "p_max", "", 0.9, 0.5, 1, false, true, false, ""}};
    std::string name() const override { return name_; }
    std::string description() const override { return ""; }
    std::string reference() const override { return ""; }
    std::vector<MethodParameter> parameters() const override { return params_; }
    std::vector<ParameterRelation> relations() const override { return {}; }
    MapRule rule(const MethodValues&, const RuleContext&) const override { return {}; }
  };
  auto no_p_min = std::make_shared<Broken>();
  CHECK_THROWS_WITH(registerMethod(no_p_min), Catch::Contains("needs a parameter p_min"));
  auto bad_name = std::make_shared<Broken>();
  bad_name->name_ = "Bad Name";
  CHECK_THROWS_WITH(registerMethod(bad_name), Catch::Contains("lower-case letters"));
  // A map setting's name (results key the settings beside the parameters), p_t, or one no flag can spell. Names
  // of map's own flags are the command's to refuse (test_map_methods: "... named like one of map's flags ...").
  for (const char* reserved : {"resolution", "s_c", "variant", "stats", "p_t", "Radius", "two words", "9k"}) {
    auto clash = std::make_shared<Broken>();
    clash->params_ = {{"p_max", "p_max", "", 0.9, 0.5, 1, false, true, false, ""},
                      {"p_min", "p_min", "", 0.1, 0, 0.5, false, true, false, ""},
                      {reserved, reserved, "", 1, 0, 2, false, false, false, ""}};
    INFO(reserved);
    CHECK_THROWS_WITH(registerMethod(clash), Catch::Contains("a parameter name is [a-z][a-z0-9_]*"));
  }
  CHECK_THROWS_WITH(findMethod("nope"), Catch::Contains("knn, octomap"));
  const auto listed = test::runCli("methods");
  CHECK(listed.exit_code == 0);
  for (const char* name : {"octomap:", "knn:", "sor-octomap:", "ror-octomap:", "range-octomap:", "std_mul", "min_neighbors"})
    CHECK(listed.output.find(name) != std::string::npos);
}
