// Observable truth (docs/results-format.md, "Truth"): hand-built scenes whose observable voxels are known, a
// property test against a deliberately plain oracle (liboctomap's computeRayKeys, a KeySet and nested loops), and
// the evaluation option through sweep, merge and compare.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <fstream>

#include <octomap/OcTree.h>

#include "occsweep/core/splitmix64.hpp"
#include "occsweep/eval/builtin_scene.hpp"
#include "occsweep/eval/confusion.hpp"
#include "occsweep/eval/observable_truth.hpp"
#include "occsweep/eval/truth_coverage.hpp"
#include "occsweep/sweeps/sweep.hpp"
#include "test_helpers.hpp"

using namespace occsweep;
namespace fs = std::filesystem;
using octomap::point3d;

namespace {

constexpr double kResolution = 0.1;

// Box bounds fall inside voxels (x.x2 to x.x8), never on a voxel boundary, so which voxels a box fills is plain.
GroundTruth truthOfBoxes(const std::vector<AxisBox>& boxes) {
  TruthSources sources;
  sources.boxes = boxes;
  return makeGroundTruth(sources, AxisBox{{-1.0, -2.0, -1.0}, {4.0, 2.0, 2.0}}, kResolution);
}

// The oracle, written from the definition alone: for every truth voxel, origin within s_c of its centre, and aim
// point (the centre, and each face centre a hundredth of a voxel inside), liboctomap's own computeRayKeys (origin
// voxel included, end voxel excluded); any key of the ray in the truth blocks it.
octomap::KeySet oracleObservable(const GroundTruth& truth, const std::vector<point3d>& origins, double s_c) {
  octomap::OcTree tree(truth.resolution);
  const float inside = float(0.49 * truth.resolution);
  const point3d offsets[7] = {{0, 0, 0},       {inside, 0, 0}, {-inside, 0, 0}, {0, inside, 0},
                              {0, -inside, 0}, {0, 0, inside}, {0, 0, -inside}};
  octomap::KeyRay ray;  // allocated once: a KeyRay holds room for 100,000 keys
  octomap::KeySet seen;
  for (const auto& key : truth.occupied) {
    const point3d centre = tree.keyToCoord(key);
    for (const auto& origin : origins) {
      if (!((centre - origin).norm() <= s_c)) continue;
      for (const point3d& offset : offsets) {
        const point3d aim = centre + offset;
        if (tree.coordToKey(aim) != key || !tree.computeRayKeys(origin, aim, ray)) continue;
        bool blocked = false;
        for (const auto& k : ray) blocked = blocked || truth.occupied.count(k) > 0;
        if (!blocked) seen.insert(key);
      }
    }
  }
  return seen;
}

// KeySet (std::tr1::unordered_set) has no ==: compared as sorted key lists.
std::vector<std::array<int, 3>> sorted(const octomap::KeySet& keys) {
  std::vector<std::array<int, 3>> v;
  for (const auto& k : keys) v.push_back({k[0], k[1], k[2]});
  std::sort(v.begin(), v.end());
  return v;
}

octomap::OcTreeKey keyOf(const point3d& p) {
  const octomap::OcTree tree(kResolution);
  return tree.coordToKey(p);
}

const point3d kOrigin(0.05f, 0.03f, 0.51f);

}  // namespace

TEST_CASE("a box hidden behind a wall has no observable voxel, the wall's near face is all that is seen") {
  const AxisBox wall{{1.02, -1.48, -0.48}, {1.08, 1.48, 1.48}};
  const AxisBox box{{1.52, -0.18, 0.32}, {1.78, 0.28, 0.68}};
  const GroundTruth truth = truthOfBoxes({wall, box});
  const octomap::KeySet seen = observableTruthVoxels(truth, {kOrigin}, 4.0);
  const int wall_layer = keyOf(point3d(1.05f, 0, 0))[0];
  REQUIRE(!seen.empty());
  for (const auto& k : seen) CHECK(k[0] == wall_layer);  // no box voxel, every seen voxel of the wall
}

TEST_CASE("a one-voxel-thick wall seen head-on counts exactly its voxels") {
  // 6 x 6 voxels: y from -0.3 to 0.3, z from 0.2 to 0.8, one layer at x = 1.0 to 1.1.
  const GroundTruth truth = truthOfBoxes({AxisBox{{1.02, -0.28, 0.22}, {1.08, 0.28, 0.78}}});
  REQUIRE(truth.occupied.size() == 36);
  CHECK(sorted(observableTruthVoxels(truth, {kOrigin}, 4.0)) == sorted(truth.occupied));
}

TEST_CASE("a solid box seen from one side along an axis shows exactly its front face") {
  // 4 layers deep (x 1.0 to 1.4), 5 x 5 voxels across, the origin on the box's axis in front of it.
  const GroundTruth truth = truthOfBoxes({AxisBox{{1.02, -0.18, 0.32}, {1.38, 0.28, 0.78}}});
  REQUIRE(truth.occupied.size() == 100);
  octomap::KeySet front;
  const int front_layer = keyOf(point3d(1.05f, 0, 0))[0];
  for (const auto& k : truth.occupied)
    if (k[0] == front_layer) front.insert(k);
  REQUIRE(front.size() == 25);
  CHECK(sorted(observableTruthVoxels(truth, {kOrigin}, 4.0)) == sorted(front));
  // Seen from both ends, both end faces and nothing of the inside.
  octomap::KeySet ends = front;
  const int back_layer = keyOf(point3d(1.35f, 0, 0))[0];
  for (const auto& k : truth.occupied)
    if (k[0] == back_layer) ends.insert(k);
  CHECK(sorted(observableTruthVoxels(truth, {kOrigin, point3d(2.45f, 0.03f, 0.51f)}, 4.0)) == sorted(ends));
}

TEST_CASE("a flat top seen at 15-19 degrees is observable in full, as the cameras of the rendered sets see it") {
  // A slab 7 x 7 voxels wide and 2 layers high (z 0.0 to 0.2), seen from 2.0 to 2.7 m away and 0.7 m above its top,
  // as the rendered data sets' cameras see the boxes' tops. A ray aimed at a top voxel's centre would cross the next
  // top voxel first (below 45 degrees); its top face's centre is reached. Under the top layer only the near side
  // of the bottom layer is seen.
  const GroundTruth truth = truthOfBoxes({AxisBox{{1.02, -0.28, 0.02}, {1.68, 0.38, 0.18}}});
  REQUIRE(truth.occupied.size() == 98);
  const int top = keyOf(point3d(1.05f, 0, 0.15f))[2], near_row = keyOf(point3d(1.05f, 0, 0))[0];
  octomap::KeySet expected;
  for (const auto& k : truth.occupied)
    if (k[2] == top || k[0] == near_row) expected.insert(k);
  REQUIRE(expected.size() == 49 + 7);
  CHECK(sorted(observableTruthVoxels(truth, {point3d(-1.0f, 0.05f, 0.9f)}, 4.0)) == sorted(expected));
}

TEST_CASE("truth beyond s_c of every origin is not observable") {
  const GroundTruth truth = truthOfBoxes({AxisBox{{1.02, -0.28, 0.22}, {1.08, 0.28, 0.78}}});
  CHECK(observableTruthVoxels(truth, {kOrigin}, 0.9).empty());  // the nearest centre is 1.0 m away
  // At s_c = 1.03 exactly the voxels whose centre lies within 1.03 m of the origin (the wall's middle).
  const octomap::OcTree tree(kResolution);
  octomap::KeySet near;
  for (const auto& k : truth.occupied)
    if ((tree.keyToCoord(k) - kOrigin).norm() <= 1.03) near.insert(k);
  REQUIRE(!near.empty());
  REQUIRE(near.size() < truth.occupied.size());
  CHECK(sorted(observableTruthVoxels(truth, {kOrigin}, 1.03)) == sorted(near));
}

TEST_CASE("an origin inside a truth voxel sees that voxel and nothing else") {
  const GroundTruth truth = truthOfBoxes({AxisBox{{0.02, -0.08, 0.42}, {0.08, 0.08, 0.58}},  // holds kOrigin
                                          AxisBox{{1.02, -0.28, 0.22}, {1.08, 0.28, 0.78}}});
  const octomap::OcTreeKey own = keyOf(kOrigin);
  CHECK(sorted(observableTruthVoxels(truth, {kOrigin}, 4.0)) == std::vector<std::array<int, 3>>{{own[0], own[1], own[2]}});
}

TEST_CASE("observable truth equals the computeRayKeys oracle on 60 random scenes") {
  std::size_t seen_total = 0, hidden_total = 0;  // the scenes must exercise both outcomes
  for (std::uint64_t seed = 1; seed <= 60; ++seed) {
    SplitMix64 rng(seed);
    std::vector<AxisBox> boxes;
    for (std::size_t b = 0, n = 1 + rng.below(4); b < n; ++b) {
      AxisBox box;
      for (int i = 0; i < 3; ++i) {
        box.min[i] = -0.5 + 2.0 * rng.uniform();
        box.max[i] = box.min[i] + 0.05 + 0.5 * rng.uniform();
      }
      boxes.push_back(box);
    }
    std::vector<point3d> origins;
    for (std::size_t o = 0, n = 1 + rng.below(5); o < n; ++o)
      origins.emplace_back(float(-0.9 + 3.5 * rng.uniform()), float(-1.5 + 3.0 * rng.uniform()),
                           float(-0.5 + 2.0 * rng.uniform()));
    const double s_c = 0.5 + 3.0 * rng.uniform();
    const GroundTruth truth = truthOfBoxes(boxes);
    INFO("seed " << seed << ", " << truth.occupied.size() << " truth voxels, " << origins.size() << " origins");
    const octomap::KeySet seen = observableTruthVoxels(truth, origins, s_c);
    CHECK(sorted(seen) == sorted(oracleObservable(truth, origins, s_c)));
    seen_total += seen.size(), hidden_total += truth.occupied.size() - seen.size();
  }
  CHECK(seen_total > 100);
  CHECK(hidden_total > 100);
}

// The median of every region point's distance to its nearest truth voxel centre, over all centres (capped as the
// search is), written from the definition: no shells, no sample.
double oracleMedianDistance(const GroundTruth& truth, const PointCloudSet& scans) {
  const octomap::OcTree tree(truth.resolution);
  std::vector<double> d;
  for (const Scan& scan : scans)
    for (const point3d& p : scan.points) {
      if (!truth.inRegion(tree.coordToKey(p))) continue;
      double best = (kPointSearchVoxels + 0.5) * truth.resolution;
      for (const auto& key : truth.occupied) best = std::min(best, double((tree.keyToCoord(key) - p).norm()));
      d.push_back(best);
    }
  std::sort(d.begin(), d.end());
  return d.size() % 2 ? d[d.size() / 2] : (d[d.size() / 2 - 1] + d[d.size() / 2]) / 2;
}

TEST_CASE("truth coverage: the observable share is the oracle's and the median distance a brute-force search's") {
  for (std::uint64_t seed = 1; seed <= 30; ++seed) {
    SplitMix64 rng(seed);
    const GroundTruth truth = truthOfBoxes({{{-0.42, -0.38, -0.12}, {0.18 + rng.uniform(), 0.32, 0.48}},
                                            {{1.02, -1.18, 0.02}, {1.48, -0.52 + rng.uniform(), 1.28}}});
    PointCloudSet scans;
    for (std::size_t s = 0, n = 1 + rng.below(3); s < n; ++s) {
      Scan& scan = scans.emplace_back();
      scan.origin = point3d(float(-0.9 + 3.5 * rng.uniform()), float(-1.5 + 3.0 * rng.uniform()), 1.5f);
      // Points near the first box, and anywhere (up to 2 m from a box: past the search's bound; some outside the
      // region).
      for (std::size_t i = 0; i < 300; ++i)
        scan.points.emplace_back(i % 3 ? point3d(float(-0.6 + rng.uniform()), float(-0.6 + rng.uniform()),
                                                 float(-0.3 + rng.uniform()))
                                       : point3d(float(-1.5 + 6.0 * rng.uniform()), float(-2.5 + 5.0 * rng.uniform()),
                                                 float(-0.2 + 1.5 * rng.uniform())));
    }
    const double s_c = 0.5 + 3.0 * rng.uniform();
    INFO("seed " << seed << ", " << truth.occupied.size() << " truth voxels");
    const TruthCoverage c = measureTruthCoverage(truth, scans, s_c);
    REQUIRE(c.sampled_truth == truth.occupied.size());  // fewer than the sample: all tested
    std::vector<point3d> origins;
    for (const Scan& scan : scans) origins.push_back(scan.origin);
    CHECK(c.observable_sampled == oracleObservable(truth, origins, s_c).size());
    CHECK(c.points == pointCount(scans));
    CHECK(c.sampled_points == c.points_in_region);
    CHECK(c.points_in_region < c.points);
    CHECK(c.median_point_distance == Approx(oracleMedianDistance(truth, scans)).margin(1e-9));
    CHECK(c.median_point_distance < kPointSearchVoxels * kResolution);  // a median the search found, not its bound
  }
}

TEST_CASE("truth coverage from the truth's sources equals the one from its key set, sample and offset included") {
  // import truth measures from the sources without the key set (truth_mask.hpp); sweep from the key set it scores.
  for (std::uint64_t seed = 1; seed <= 12; ++seed) {
    SplitMix64 rng(seed);
    TruthSources sources;
    sources.boxes.push_back({{-0.95, -1.95, -0.45}, {2.0 + 1.9 * rng.uniform(), 1.95, -0.05}});  // a floor
    sources.boxes.push_back({{0.2, 0.1, 0.0}, {0.2 + rng.uniform(), 0.9, 0.7}});  // overlaps the floor's voxels
    const point3d a(float(-0.5 + rng.uniform()), -1.5f, 0.1f), b(2.5f, float(rng.uniform()), 1.8f);
    sources.mesh.push_back({{a, b, point3d(0.3f, 1.6f, 0.4f)}});
    for (int i = 0; i < 40; ++i)  // points, some in the boxes' voxels, some outside the region
      sources.points.emplace_back(float(-1.5 + 6.0 * rng.uniform()), float(-2.5 + 5.0 * rng.uniform()), 0.5f);
    const AxisBox region{{-1.0, -2.0, -1.0}, {4.0, 2.0, 2.0}};
    const GroundTruth truth = makeGroundTruth(sources, region, kResolution);
    PointCloudSet scans(2);
    for (Scan& scan : scans) {
      scan.origin = point3d(float(3.5 * rng.uniform()), float(-1.5 + 3.0 * rng.uniform()), 1.5f);
      for (int i = 0; i < 400; ++i)
        scan.points.emplace_back(float(-1.0 + 4.0 * rng.uniform()), float(-2.0 + 4.0 * rng.uniform()), -0.1f);
    }
    INFO("seed " << seed << ", " << truth.occupied.size() << " truth voxels");
    const TruthCoverage from_keys = measureTruthCoverage(truth, scans, 4.0);
    CHECK(from_keys.truth_voxels > kCoverageTruthSample);  // the sample is a sample
    CHECK(measureTruthCoverage(sources, region, kResolution, scans, 4.0) == from_keys);
  }
}

TEST_CASE("truth coverage: no offset fits the built-in scene better than none, and its shift by 0.5 m is found") {
  const Dataset d = makeBuiltinScene();
  const TruthCoverage aligned = measureTruthCoverage(d.truth, d.region, kResolution, d.scans, 4.0);
  CHECK(coverageWarning(aligned, TruthMode::Full).empty());
  REQUIRE(aligned.offset_fit);
  CHECK(aligned.offset_fit->offset_share_on_surface < aligned.offset_fit->share_on_surface);
  for (const point3d& shift : {point3d(0.5f, 0, 0), point3d(0, -0.5f, 0), point3d(0.4f, 0.3f, 0)}) {
    INFO("scans shifted by " << shift);
    PointCloudSet shifted = d.scans;
    for (Scan& scan : shifted) {
      scan.origin += shift;
      for (point3d& p : scan.points) p += shift;
    }
    const TruthCoverage c = measureTruthCoverage(d.truth, d.region, kResolution, shifted, 4.0);
    CHECK_THAT(coverageWarning(c, TruthMode::Full), Catch::Contains("one translation fits them clearly better"));
    REQUIRE(c.offset_fit);
    for (std::size_t a = 0; a < 3; ++a) CHECK(c.offset_fit->offset[a] == Approx(-shift(int(a))).margin(0.11));
  }
}

TEST_CASE("unobservable voxels leave the evaluation: neither positive nor negative") {
  const GroundTruth full = truthOfBoxes({AxisBox{{1.02, -0.18, 0.32}, {1.38, 0.28, 0.78}}});
  const GroundTruth observable = restrictToObservable(full, {Viewpoint{kOrigin}}, 4.0);
  CHECK(observable.excluded.size() == 75);
  const octomap::OcTree empty_map(kResolution);
  const RegionSample a = sampleRegion(empty_map, full), b = sampleRegion(empty_map, observable);
  CHECK(a.positives == 100);
  CHECK(b.positives == 25);
  CHECK(b.negatives == a.negatives);
}

// ---------------------------------------------------------------------------------------------------------
// Through the sweep, results files, merge and compare.

namespace {

ResultsFile sweep(const fs::path& data, const std::string& grid, const std::string& engine, TruthMode truth,
                  const fs::path& out, SweepSelection selection = {}) {
  SweepConfig c;
  c.dataset = data;
  c.grid = grid;
  c.engine = engine;
  c.truth = truth;
  c.out = out;
  c.selection = selection;
  c.quiet = true;
  return runSweep(c);
}

// A k-NN grid small enough for a fast test: 2 maps.
fs::path smallKnnGrid(const fs::path& dir) {
  const fs::path grid = dir / "knn-small.json";
  std::ofstream(grid) << R"({"name": "knn-small", "method": "knn", "parameters": {"p_max": {"value": 0.98},
    "p_min": {"value": 0.02}, "p_m": {"value": 0.26}, "p_m_out": {"value": 0.38}, "p_u": {"value": 0.86},
    "p_l": {"min": 0.26, "max": 0.38, "step": 0.12}, "p_t": {"step": 0.12}, "k": [3]}})";
  return grid;
}

struct Scene {
  fs::path dir, solid, surface;
};

// The built-in scene (four solid boxes: their interiors unobservable), and the same scans with truth of isolated
// voxels that every scan sees from somewhere.
const Scene& scene() {
  static const Scene s = [] {
    Scene sc;
    sc.dir = test::processScratch("observable-truth");
    Dataset d = makeBuiltinScene({.seed = 3, .scans = 6, .width = 32, .height = 24});
    sc.solid = sc.dir / "solid";
    writeDataset(d, sc.solid);
    d.truth = {};
    for (double x = -0.45; x < 0.5; x += 0.3)
      for (double y = -0.45; y < 0.5; y += 0.3) d.truth.points.emplace_back(float(x), float(y), 0.25f);
    sc.surface = sc.dir / "isolated";
    writeDataset(d, sc.surface);
    return sc;
  }();
  return s;
}

std::uint64_t positives(const ResultsFile& f) {
  const auto& c = f.maps.at(0).thresholds.at(0).counts;
  return c.tp + c.fn;
}

}  // namespace

TEST_CASE("a sweep with observable truth counts fewer true voxels where box interiors exist, the same elsewhere") {
  const Scene& s = scene();
  const fs::path grid = smallKnnGrid(s.dir);
  for (const char* engine : {"replay", "direct"}) {
    INFO(engine);
    const std::string e = engine;
    const ResultsFile full = sweep(s.solid, "octomap-opt", e, TruthMode::Full, s.dir / (e + "-solid-full.json"));
    const ResultsFile obs = sweep(s.solid, "octomap-opt", e, TruthMode::Observable, s.dir / (e + "-solid-obs.json"));
    CHECK(obs.header.truth == TruthMode::Observable);
    CHECK(positives(obs) < positives(full));
    for (std::size_t m = 0; m < full.maps.size(); ++m)
      for (std::size_t t = 0; t < full.maps[m].thresholds.size(); ++t) {
        const auto &a = full.maps[m].thresholds[t].counts, &b = obs.maps[m].thresholds[t].counts;
        CHECK(a.fp == b.fp);  // only true voxels leave
        CHECK(a.tn == b.tn);
        CHECK(b.tp <= a.tp);
      }
    // Isolated truth voxels: every one observable, so both truths count alike.
    const Dataset iso = readDataset(s.surface);
    const GroundTruth gt = makeGroundTruth(iso.truth, iso.region, 0.1);
    REQUIRE(evaluatedTruth(TruthMode::Observable, gt, iso.scans, 4.0, s.surface.string()).excluded.empty());
    for (const std::string& g : {std::string("octomap-opt"), grid.string()}) {
      const std::string tag = e + "-" + fs::path(g).stem().string();
      const ResultsFile a = sweep(s.surface, g, e, TruthMode::Full, s.dir / (tag + "-iso-full.json"));
      const ResultsFile b = sweep(s.surface, g, e, TruthMode::Observable, s.dir / (tag + "-iso-obs.json"));
      REQUIRE(a.maps.size() == b.maps.size());
      for (std::size_t m = 0; m < a.maps.size(); ++m)
        for (std::size_t t = 0; t < a.maps[m].thresholds.size(); ++t)
          CHECK(a.maps[m].thresholds[t].counts == b.maps[m].thresholds[t].counts);
    }
  }
  // Both engines agree under observable truth, k-NN included.
  const ResultsFile replayed = sweep(s.solid, grid.string(), "replay", TruthMode::Observable, s.dir / "knn-replay.json");
  const ResultsFile direct = sweep(s.solid, grid.string(), "direct", TruthMode::Observable, s.dir / "knn-direct.json");
  CHECK(resultDifferences(direct, replayed).empty());
}

TEST_CASE("results files record the truth: version 2 with map.truth for observable, version 1 without for full") {
  const Scene& s = scene();
  const fs::path full = s.dir / "rec-full.json", obs = s.dir / "rec-obs.json";
  (void)sweep(s.solid, "octomap-opt", "replay", TruthMode::Full, full);
  (void)sweep(s.solid, "octomap-opt", "replay", TruthMode::Observable, obs);
  const auto j_full = nlohmann::json::parse(std::ifstream(full)), j_obs = nlohmann::json::parse(std::ifstream(obs));
  CHECK(j_full.at("version") == 1);
  CHECK(!j_full.at("map").contains("truth"));
  CHECK(j_obs.at("version") == 2);
  CHECK(j_obs.at("map").at("truth") == "observable");
  CHECK(readResults(full).header.truth == TruthMode::Full);
  // The version and the field go together: either without the other is refused, naming map.truth.
  auto refused = [&](nlohmann::json j, const char* name) {
    const fs::path edited = s.dir / name;
    std::ofstream(edited) << j.dump();
    CHECK_THROWS_WITH(readResults(edited), Catch::Contains(edited.string()) && Catch::Contains("map.truth"));
  };
  nlohmann::json v1_with_field = j_obs, v2_without = j_obs;
  v1_with_field["version"] = 1;
  v2_without["map"].erase("truth");
  refused(v1_with_field, "v1-with-truth.json");
  refused(v2_without, "v2-without-truth.json");
  // results check, against the data set too: TP+FN is the observable truth's count.
  auto check = test::runCli("results check " + obs.string() + " --dataset " + s.solid.string());
  INFO(check.output);
  CHECK(check.exit_code == 0);
  // A sweep of the other truth into the same file is other work.
  auto again = test::runCli("sweep --dataset " + s.solid.string() + " --grid octomap-opt --quiet --out " + obs.string());
  CHECK(again.exit_code == 2);
  CHECK_THAT(again.output, Catch::Contains("map.truth"));
}

TEST_CASE("merge and compare refuse to mix full and observable results, naming both files and map.truth") {
  const Scene& s = scene();
  const fs::path d = s.dir / "mix";
  fs::create_directories(d);
  const fs::path shard0 = d / "shard0-full.json", shard1 = d / "shard1-obs.json";
  (void)sweep(s.solid, "octomap-opt", "replay", TruthMode::Full, shard0, {std::nullopt, 0, 2});
  (void)sweep(s.solid, "octomap-opt", "replay", TruthMode::Observable, shard1, {std::nullopt, 1, 2});
  const auto merged = test::runCli("merge " + shard0.string() + " " + shard1.string() + " --out " + (d / "m.json").string());
  INFO(merged.output);
  CHECK(merged.exit_code == 2);
  CHECK_THAT(merged.output, Catch::Contains("shard0-full.json") && Catch::Contains("shard1-obs.json") &&
                                Catch::Contains("map.truth"));

  const fs::path om = d / "om-full.json", knn = d / "knn-obs.json";
  (void)sweep(s.solid, "octomap-opt", "replay", TruthMode::Full, om);
  (void)sweep(s.solid, smallKnnGrid(d).string(), "replay", TruthMode::Observable, knn);
  for (const char* extra : {"", " --allow-mixed"}) {
    const auto compared = test::runCli("compare " + om.string() + " " + knn.string() + extra);
    INFO(compared.output);
    CHECK(compared.exit_code == 2);
    CHECK_THAT(compared.output, Catch::Contains("om-full.json") && Catch::Contains("knn-obs.json") &&
                                    Catch::Contains("map.truth"));
  }
  // One truth: compared, and the truth is said.
  const fs::path om_obs = d / "om-obs.json";
  (void)sweep(s.solid, "octomap-opt", "replay", TruthMode::Observable, om_obs);
  const auto same = test::runCli("compare " + om_obs.string() + " " + knn.string());
  INFO(same.output);
  CHECK(same.exit_code == 0);
  CHECK_THAT(same.output, Catch::Contains("truth: observable"));
}

TEST_CASE("one pass with an observable twin gives what separate full and observable sweeps give") {
  const Scene& s = scene();
  const fs::path d = s.dir / "twin";
  fs::create_directories(d);
  const fs::path grid = smallKnnGrid(d);
  for (const std::string& g : {std::string("octomap-opt"), grid.string()})
    for (const char* engine : {"replay", "direct"}) {
      const std::string tag = fs::path(g).stem().string() + "-" + engine;
      INFO(tag);
      SweepConfig c;
      c.dataset = s.solid, c.grid = g, c.engine = engine, c.quiet = true;
      c.out = d / (tag + "-both.json");
      c.observable_out = d / (tag + "-both-observable.json");
      const ResultsFile full = runSweep(c);
      const ResultsFile twin = readResults(c.observable_out);
      CHECK(twin.header.truth == TruthMode::Observable);
      CHECK(resultDifferences(sweep(s.solid, g, engine, TruthMode::Full, d / (tag + "-full.json")), full).empty());
      CHECK(resultDifferences(sweep(s.solid, g, engine, TruthMode::Observable, d / (tag + "-obs.json")), twin).empty());
      CHECK(positives(twin) < positives(full));
    }
}

TEST_CASE("a sweep replaces a twin of other work at its observable_out only with force, and never a user's file") {
  // Old library: the twin's target was checked as if --force were given, so occsweep's results of another sweep
  // there were replaced silently.
  const Scene& s = scene();
  const fs::path d = s.dir / "twin-other-work";
  fs::create_directories(d);
  SweepConfig c;
  c.dataset = s.solid, c.grid = "octomap-opt", c.engine = "replay", c.quiet = true;
  c.out = d / "r.json";
  c.observable_out = d / "r-observable.json";
  (void)sweep(s.solid, smallKnnGrid(d).string(), "replay", TruthMode::Observable, c.observable_out);  // other work
  const std::string before = test::bytesOf(c.observable_out);
  CHECK_THROWS_WITH(runSweep(c), Catch::Contains("r-observable.json: holds results of other work") &&
                                     Catch::Contains("--force replaces it"));
  CHECK(test::bytesOf(c.observable_out) == before);
  CHECK_FALSE(fs::exists(c.out));
  // Its own twin of this very work (a kill between the two renames) is replaced without force.
  c.force = true;
  (void)runSweep(c);
  fs::remove(c.out);
  c.force = false;
  CHECK_NOTHROW(runSweep(c));
  CHECK(readResults(c.observable_out).header.truth == TruthMode::Observable);
  // A user's file: refused even with force.
  std::ofstream(c.observable_out, std::ios::trunc) << "{\"mine\": 1}\n";
  fs::remove(c.out);
  c.force = true;
  CHECK_THROWS_WITH(runSweep(c), Catch::Contains("r-observable.json") && Catch::Contains("refused even with --force"));
  CHECK(test::bytesOf(c.observable_out) == "{\"mine\": 1}\n");
}
