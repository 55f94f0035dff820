// The k-NN mapper against a second implementation written from the paper's Algorithm 1 alone
// (tests/reference/knn_algorithm1.hpp), beyond the degenerate case that equals liboctomap: k > 1, p_u != p_l,
// p'_m != p_m, several points per voxel, points beyond s_c, clamping at both bounds, both update variants and
// both statistics modes. Four library paths are checked on each random scene: the direct build on one thread
// (KnnInverseSensorModel::buildMap) and with scans recorded in parallel as `occsweep map --method knn` runs it
// (buildMap on a TBB ScanExecutor), the library's own plain path (buildMapReference), voxel for voxel with float
// equality; and
// the replay engine of `sweep`, whose confusion counts per threshold must equal those counted on the reference
// map against the same ground truth.
#include <catch2/catch.hpp>

#include <cstdio>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "occsweep/methods/knn/knn_method.hpp"
#include "occsweep/methods/knn/knn_inverse_sensor_model.hpp"
#include "occsweep/methods/knn/knn_set_distances.hpp"
#include "occsweep/core/map_voxels.hpp"
#include "occsweep/core/splitmix64.hpp"
#include "occsweep/eval/confusion.hpp"
#include "occsweep/eval/ground_truth.hpp"
#include "occsweep/sweeps/replay.hpp"
#include "occsweep/sweeps/tbb_scan_executor.hpp"
#include "reference/knn_algorithm1.hpp"

using namespace occsweep;
using reference::LogOddsMap;

namespace {

constexpr int kScenes = 25;

/// A small random scene: boxes, scans of noisy box-surface points with clusters and exact duplicates (several
/// points per voxel), floaters, points beyond s_c, sometimes a point exactly at s_c, a scan with a lone in-range
/// point (s = +inf) or a first scan of two in-range points (online sigma = 0).
struct Scene {
  PointCloudSet set;
  std::vector<AxisBox> boxes;
  AxisBox region;
  double resolution = 0.1, s_c = 2.0;
};

double between(SplitMix64& rng, double lo, double hi) { return lo + (hi - lo) * rng.uniform(); }

/// A multiple of 1/64 (exact in float), so that origin + (s_c, 0, 0) is exactly s_c away.
float grid64(double v) { return float(std::round(v * 64.0) / 64.0); }

octomap::point3d surfacePoint(SplitMix64& rng, const AxisBox& b, double noise) {
  double p[3];
  for (int a = 0; a < 3; ++a) p[a] = between(rng, b.min[a], b.max[a]);
  const int axis = int(rng.below(3));
  p[axis] = rng.below(2) ? b.min[axis] : b.max[axis];  // on one face
  return {float(p[0] + noise * rng.gaussian()), float(p[1] + noise * rng.gaussian()),
          float(p[2] + noise * rng.gaussian())};
}

Scan randomScan(SplitMix64& rng, const Scene& scene, std::size_t t) {
  Scan scan;
  const double angle = between(rng, 0, 6.283185307179586), radius = between(rng, 1.2, 2.6);
  scan.origin = {grid64(radius * std::cos(angle)), grid64(radius * std::sin(angle)), grid64(between(rng, 0.3, 1.0))};
  auto& pts = scan.points;
  const double noise = between(rng, 0.005, 0.06);
  const std::size_t surface = 25 + rng.below(40);
  for (std::size_t i = 0; i < surface; ++i) {
    pts.push_back(surfacePoint(rng, scene.boxes[rng.below(scene.boxes.size())], noise));
    const std::size_t copies = rng.below(4);  // a cluster in (mostly) the same voxel
    for (std::size_t c = 0; c < copies; ++c)
      pts.push_back(rng.below(3) == 0 ? pts.back()
                                      : pts.back() + octomap::point3d(float(0.01 * rng.gaussian()),
                                                                      float(0.01 * rng.gaussian()),
                                                                      float(0.01 * rng.gaussian())));
  }
  for (int i = 0; i < 6; ++i)  // floaters: isolated points, large s
    pts.emplace_back(float(between(rng, -1.5, 1.5)), float(between(rng, -1.5, 1.5)), float(between(rng, 0, 1.4)));
  for (int i = 0; i < 6; ++i) {  // beyond s_c: only their cut rays count
    const double az = between(rng, 0, 6.283185307179586), el = between(rng, -0.3, 0.4);
    const double d = scene.s_c * between(rng, 1.02, 2.0);
    pts.push_back(scan.origin + octomap::point3d(float(d * std::cos(el) * std::cos(az)),
                                                 float(d * std::cos(el) * std::sin(az)), float(d * std::sin(el))));
  }
  if (rng.below(3) == 0) pts.push_back(scan.origin + octomap::point3d(float(scene.s_c), 0, 0));  // at s_c: inner
  // Rare shapes of z_in: a lone in-range point (s = +inf, left out of mu and sigma), or, first, two points
  // (in online mode sigma = 0 after scan 0: F is a step).
  const auto rare = rng.below(6);
  if (rare == 0 || (rare == 1 && t == 0)) {
    const std::size_t keep = rare == 0 ? 1 : 2;
    std::vector<octomap::point3d> kept;
    for (const auto& p : pts)
      if (!reference::isInner(p, scan.origin, scene.s_c) || kept.size() < keep) kept.push_back(p);
    pts.swap(kept);
  }
  return scan;
}

Scene randomScene(std::uint64_t seed) {
  SplitMix64 rng(seed);
  Scene scene;
  const double resolutions[] = {0.1, 0.15, 0.2};
  scene.resolution = resolutions[rng.below(3)];
  scene.s_c = 0.75 + 0.25 * double(rng.below(8));  // 0.75 .. 2.5 m, exact in float
  const std::size_t boxes = 1 + rng.below(3);
  for (std::size_t b = 0; b < boxes; ++b) {
    AxisBox box;
    for (int a = 0; a < 3; ++a) {
      box.min[a] = a == 2 ? between(rng, 0, 0.3) : between(rng, -1, 0.6);
      box.max[a] = box.min[a] + between(rng, 0.15, 0.7);
    }
    scene.boxes.push_back(box);
  }
  scene.region = {{-1.3, -1.3, -0.1}, {1.3, 1.3, 1.1}};  // smaller than where points fall: outside voxels exist
  const std::size_t scans = 3 + rng.below(5);
  for (std::size_t t = 0; t < scans; ++t) scene.set.push_back(randomScan(rng, scene, t));
  return scene;
}

/// Parameters off the degenerate case: hundredths obeying Eq. 12 with p_u > p_l and p'_m > p_m strictly.
/// k-NN's values (KnnMethod::parameters' order: k, p_u, p_l, p_max, p_min, p_m, p_m_out).
MethodValues randomMapParams(SplitMix64& rng, int k, Fixed p_u, Fixed p_l) {
  auto hundredths = [&](int lo, int hi) { return Fixed(lo + int(rng.below(std::uint64_t(hi - lo + 1)))) * 10'000; };
  const Fixed p_max = hundredths(52, 97);  // low values clamp often
  const Fixed p_min = hundredths(3, 40);
  const Fixed p_m = p_min + hundredths(0, int(48 - p_min / 10'000));
  const Fixed p_m_out = p_m + hundredths(1, int(49 - p_m / 10'000));
  return {double(k), toDouble(p_u), toDouble(p_l), toDouble(p_max), toDouble(p_min), toDouble(p_m), toDouble(p_m_out)};
}

KnnParams knnParams(const MethodValues& m, const Scene& scene, UpdateVariant variant, StatsMode stats) {
  return KnnMethod().knnParams(m, {{scene.resolution, scene.s_c, variant, stats}, {}, {}});
}

/// Thresholds: the grid's p_min..p_max by 0.12, plus probabilities whose log-odds voxels hold exactly.
std::vector<double> thresholds(const KnnParams& p) {
  std::vector<double> t;
  for (double v = p.p_min; v <= p.p_max + 1e-9; v += 0.12) t.push_back(v);
  for (double v : {p.p_max, p.p_m, p.p_m_out, p.p_u, p.p_l})
    if (v >= p.p_min && v <= p.p_max) t.push_back(v);
  return t;
}

std::string keyText(const octomap::OcTreeKey& k) {
  std::ostringstream s;
  s << "(" << k[0] << "," << k[1] << "," << k[2] << ")";
  return s.str();
}

/// Every difference between the reference map and a library map: keys on one side only, or unequal floats.
std::vector<std::string> mapDifferences(const LogOddsMap& ref, const VoxelLogOdds& lib) {
  std::vector<std::string> diffs;
  for (const auto& [key, value] : ref) {
    const auto it = lib.find(key);
    if (it == lib.end()) diffs.push_back("voxel " + keyText(key) + " only in the reference");
    else if (it->second != value) {
      char text[160];
      std::snprintf(text, sizeof text, "voxel %s: reference %.9g, library %.9g", keyText(key).c_str(), value,
                    it->second);
      diffs.push_back(text);
    }
  }
  for (const auto& [key, value] : lib)
    if (!ref.count(key)) diffs.push_back("voxel " + keyText(key) + " only in the library");
  return diffs;
}

/// What the reference map says about each region voxel (the region's keys in plain loops).
struct RegionVoxel {
  bool truly_occupied = false, known = false;
  float log_odds = 0;
};

std::vector<RegionVoxel> regionOf(const LogOddsMap& m, const GroundTruth& truth) {
  std::vector<RegionVoxel> region;
  for (int x = truth.region_min_key[0]; x <= truth.region_max_key[0]; ++x)
    for (int y = truth.region_min_key[1]; y <= truth.region_max_key[1]; ++y)
      for (int z = truth.region_min_key[2]; z <= truth.region_max_key[2]; ++z) {
        const octomap::OcTreeKey key(x, y, z);
        const auto it = m.find(key);
        region.push_back({truth.occupied.count(key) > 0, it != m.end(), it != m.end() ? it->second : 0.0f});
      }
  return region;
}

/// Occupied at p_t (docs/definitions.md, Occupied at a threshold) counted on the reference map: known and
/// log-odds >= l(p_t) in float.
ConfusionCounts countsOf(const std::vector<RegionVoxel>& region, double p_t) {
  const float threshold = reference::logOddsEq2(p_t);
  ConfusionCounts c;
  for (const RegionVoxel& v : region) {
    const bool occupied = v.known && v.log_odds >= threshold;
    (v.truly_occupied ? (occupied ? c.tp : c.fn) : (occupied ? c.fp : c.tn))++;
  }
  return c;
}

std::string countsText(const ConfusionCounts& c) {
  std::ostringstream s;
  s << "TP " << c.tp << " FP " << c.fp << " FN " << c.fn << " TN " << c.tn;
  return s.str();
}

std::string paramsText(const KnnParams& p) {
  std::ostringstream s;
  s << "k " << p.k << " p_u " << p.p_u << " p_l " << p.p_l << " p_m " << p.p_m << " p'_m " << p.p_m_out << " p_max "
    << p.p_max << " p_min " << p.p_min << " res " << p.map.resolution << " s_c " << p.map.s_c
    << (p.map.variant == UpdateVariant::Literal ? " literal" : " default")
    << (p.map.stats == StatsMode::Online ? " online" : " batch");
  return s.str();
}

/// What the scenes exercised, so that the test fails if the generator stops reaching a case it claims to cover.
struct Coverage {
  std::size_t maps = 0, voxels = 0, thresholds = 0, multi_point_voxels = 0, points_beyond = 0, lone_scans = 0,
              online_steps = 0, points_at_s_c = 0, at_l_max = 0, at_l_min = 0, clamped_hit_sums = 0, ks_seen = 0;
  bool k_seen[11] = {};
};

void countSceneCoverage(const Scene& scene, Coverage& cov) {
  const octomap::OcTree grid(scene.resolution);
  for (const auto& scan : scene.set) {
    const auto z_in = reference::innerPointsOf(scan, scene.s_c);
    cov.points_beyond += scan.points.size() - z_in.size();
    for (const auto& p : scan.points) cov.points_at_s_c += (p - scan.origin).norm() == scene.s_c;
    if (z_in.size() == 1) ++cov.lone_scans;
    std::map<octomap::OcTreeKey, int, reference::KeyLess> per_voxel;
    for (const auto& p : z_in) ++per_voxel[grid.coordToKey(p)];
    for (const auto& [_, n] : per_voxel) cov.multi_point_voxels += n > 1;
  }
  const auto online = reference::statsPerScan(reference::averageDistances(scene.set, 2, scene.s_c), StatsMode::Online);
  for (std::size_t t = 0; t < scene.set.size(); ++t)  // sigma = 0 over finite s_i: F is a step at mu
    cov.online_steps += online[t].sigma == 0.0 && reference::innerPointsOf(scene.set[t], scene.s_c).size() >= 2;
}

void countMapCoverage(const LogOddsMap& m, const KnnParams& p, Coverage& cov) {
  ++cov.maps;
  cov.voxels += m.size();
  for (const auto& [_, v] : m) {
    cov.at_l_max += v == reference::logOddsEq2(p.p_max);
    cov.at_l_min += v == reference::logOddsEq2(p.p_min);
  }
}

/// How many hit voxels of the set have a per-scan sum l(p(s_j)) beyond [l_min, l_max] (line 6's clamp matters).
std::size_t clampedHitSums(const Scene& scene, const KnnParams& p, const reference::SetDistances& s) {
  const octomap::OcTree grid(p.map.resolution);
  const auto stats = reference::statsPerScan(s, p.map.stats);
  const float l_min = reference::logOddsEq2(p.p_min), l_max = reference::logOddsEq2(p.p_max);
  std::size_t n = 0;
  for (std::size_t t = 0; t < scene.set.size(); ++t) {
    const auto z_in = reference::innerPointsOf(scene.set[t], p.map.s_c);
    LogOddsMap sums;
    for (std::size_t i = 0; i < z_in.size(); ++i)
      sums[grid.coordToKey(z_in[i])] += reference::logOddsEq2(reference::probabilityEq6(s[t][i], stats[t], p));
    for (const auto& [_, sum] : sums) n += sum < l_min || sum > l_max;
  }
  return n;
}

/// The direct build, on one thread and as `occsweep map --method knn` runs it, and the library's plain path,
/// voxel for voxel.
void requireLibraryMapsEqual(const LogOddsMap& ref, const KnnParams& p, const Scene& scene,
                             const KnnSetDistances& distances) {
  const KnnInverseSensorModel model(p);
  const auto build = [&](const std::string& path) {
    if (path == "buildMap") return model.buildMap(scene.set);
    if (path == "buildMapReference") return model.buildMapReference(scene.set, distances);
    // `occsweep map`'s path: scans recorded in parallel, batches of 1, 2, 3 scans (batch ends inside the set)
    const std::size_t batch = std::size_t(path.back() - '0');
    const ScanExecutor tbb = tbbScanExecutor();
    return model.buildMap(scene.set, computeKnnDistances(scene.set, p.k, p.map.s_c, tbb), tbb, batch);
  };
  for (const std::string path : {"buildMap", "buildMapReference", "buildMap on TBB batch 1",
                                 "buildMap on TBB batch 2", "buildMap on TBB batch 3"}) {
    INFO("library path " << path);
    const auto tree = build(path);
    const auto diffs = mapDifferences(ref, voxelLogOdds(*tree));
    for (std::size_t i = 0; i < std::min<std::size_t>(diffs.size(), 5); ++i) UNSCOPED_INFO(diffs[i]);
    REQUIRE(diffs.empty());
  }
}

/// The replay engine's counts (all lanes in one pass, and one lane alone) against the reference maps' counts.
void requireReplayEqual(const RecordedSet& recorded, const std::vector<ReplayRule>& rules,
                        const std::vector<std::vector<double>>& p_t,
                        const std::vector<std::vector<RegionVoxel>>& reference_regions,
                        const std::vector<std::string>& lane_names, Coverage& cov) {
  const auto replayed = replayCounts(recorded, rules, p_t);
  REQUIRE(replayed.size() == rules.size());
  for (std::size_t lane = 0; lane < rules.size(); ++lane) {
    INFO(lane_names[lane]);
    const RegionSample one_map = replay(recorded, rules[lane]);
    REQUIRE(replayed[lane].size() == p_t[lane].size());
    for (std::size_t t = 0; t < p_t[lane].size(); ++t) {
      const ConfusionCounts expected = countsOf(reference_regions[lane], p_t[lane][t]);
      INFO("p_t " << p_t[lane][t] << ": reference " << countsText(expected) << "; replayCounts "
                  << countsText(replayed[lane][t]) << "; replay " << countsText(classify(one_map, p_t[lane][t])));
      REQUIRE(replayed[lane][t] == expected);
      REQUIRE(classify(one_map, p_t[lane][t]) == expected);
      ++cov.thresholds;
    }
  }
}

void printAndRequireCoverage(Coverage& cov) {
  for (bool seen : cov.k_seen) cov.ks_seen += seen;
  std::cout << "test_knn_reference: " << kScenes << " scenes, " << cov.maps << " maps, " << cov.voxels
            << " voxels compared per library path, " << cov.thresholds << " thresholds compared with replay; "
            << cov.ks_seen << " values of k; " << cov.multi_point_voxels << " scan-voxels with several points, "
            << cov.points_beyond << " points beyond s_c, " << cov.points_at_s_c << " exactly at s_c, "
            << cov.lone_scans << " scans with a lone in-range point, "
            << cov.online_steps << " scans with online sigma = 0; " << cov.at_l_max << " voxels at l_max, "
            << cov.at_l_min << " at l_min, " << cov.clamped_hit_sums << " clamped hit sums\n";
  // The claim covers these cases only if the scenes reached them.
  CHECK(cov.ks_seen >= 6);
  CHECK(cov.multi_point_voxels > 0);
  CHECK(cov.points_beyond > 0);
  CHECK(cov.points_at_s_c > 0);
  CHECK(cov.lone_scans > 0);
  CHECK(cov.online_steps > 0);
  CHECK(cov.at_l_max > 0);
  CHECK(cov.at_l_min > 0);
  CHECK(cov.clamped_hit_sums > 0);
}

}  // namespace

TEST_CASE("the k-NN mapper equals a second implementation of Algorithm 1 on 25 random scenes, k > 1") {
  Coverage cov;
  for (std::uint64_t seed = 1; seed <= kScenes; ++seed) {
    const Scene scene = randomScene(1000 + seed);
    INFO("scene seed " << 1000 + seed);
    countSceneCoverage(scene, cov);
    const GroundTruth truth = makeGroundTruth({scene.boxes, {}, {}}, scene.region, scene.resolution);
    const RecordedSet recorded = recordSet(scene.set, truth, scene.resolution, scene.s_c);
    SplitMix64 rng(seed);
    for (int hit_rule = 0; hit_rule < 2; ++hit_rule) {
      // One hit rule (k, p_u, p_l) and three lanes of other parameters, replayed together as `sweep` does.
      const int k = 2 + int(rng.below(9));
      cov.k_seen[k] = true;
      const Fixed p_l = Fixed(2 + rng.below(80)) * 10'000;
      const Fixed p_u = p_l + Fixed(1 + rng.below(std::uint64_t(98 - p_l / 10'000))) * 10'000;
      std::vector<MethodValues> lanes;
      for (int lane = 0; lane < 3; ++lane) lanes.push_back(randomMapParams(rng, k, p_u, p_l));
      const KnnSetDistances distances = computeKnnDistances(scene.set, k, scene.s_c);
      const reference::SetDistances reference_s = reference::averageDistances(scene.set, k, scene.s_c);
      for (const StatsMode stats : {StatsMode::Batch, StatsMode::Online}) {
        const MapRule hit_rule = KnnMethod().rule(lanes[0], {{.s_c = scene.s_c, .stats = stats}});
        const std::vector<double> features = recordedHitFeatures(recorded, scene.set, *hit_rule.hit.feature, scene.s_c);
        const auto sums = eventHits(recorded, features, hit_rule.hit);
        for (const UpdateVariant variant : {UpdateVariant::Default, UpdateVariant::Literal}) {
          std::vector<ReplayRule> rules;
          std::vector<std::vector<double>> p_t;
          std::vector<std::vector<RegionVoxel>> reference_regions;
          std::vector<std::string> lane_names;
          for (const MethodValues& m : lanes) {
            const KnnParams p = knnParams(m, scene, variant, stats);
            lane_names.push_back(paramsText(p));
            INFO(lane_names.back());
            const LogOddsMap ref = reference::buildMap(scene.set, p, reference_s);
            countMapCoverage(ref, p, cov);
            cov.clamped_hit_sums += clampedHitSums(scene, p, reference_s);
            requireLibraryMapsEqual(ref, p, scene, distances);
            reference_regions.push_back(regionOf(ref, truth));
            rules.push_back(replayRule(KnnMethod().rule(m, {{.variant = variant}}), &sums));
            p_t.push_back(thresholds(p));
          }
          requireReplayEqual(recorded, rules, p_t, reference_regions, lane_names, cov);
        }
      }
    }
  }
  printAndRequireCoverage(cov);
}

// Lines 3-10 leave one choice open: Eq. 7 with Eq. 5 adds sum_j l(p(s_j)) to the map and clamps the result, while
// docs/design.md clamps the voxel's sum to [l_min, l_max] before adding it (line 6's m'.UpdateNode). They differ
// only when l(p(s)) leaves [l_min, l_max], which knn-opt's p_max = 0.98, p_min = 0.02 rule out for a lone point
// but the reduction grid allows (p_u up to 0.98 with p_max down to 0.5). Pinned on a hand-computed case: both
// implementations follow docs/design.md.
TEST_CASE("a hit whose l(p(s)) exceeds l_max adds only l_max to a voxel freed before (docs/design.md's reading)") {
  KnnParams p;
  p.k = 2, p.p_u = 0.9, p.p_l = 0.8, p.p_m = 0.3, p.p_m_out = 0.4, p.p_max = 0.6, p.p_min = 0.12, p.p_t = 0.5;
  const octomap::point3d origin(0.05f, 0.05f, 0.05f), in_v(0.55f, 0.05f, 0.05f);
  const PointCloudSet set = {
      {origin, {{1.05f, 0.05f, 0.05f}}, {}},  // scan 0: its ray frees voxel V (the one holding in_v) with l(p_m)
      {origin, {in_v, {0.55f, 0.55f, 0.05f}}, {}},  // scan 1: a point in V, its neighbour 0.5 m away; F = 1, p = p_l
  };
  const octomap::OcTree grid(p.map.resolution);
  const octomap::OcTreeKey v = grid.coordToKey(in_v);
  // l(p_m) + clamp(l(p_l)) in float: l(0.8) = 1.386 > l_max = l(0.6) = 0.405, so V ends at -0.442 (free at 0.5);
  // Eq. 7 with Eq. 5 alone would give min(-0.847 + 1.386, 0.405) = l_max (occupied).
  const float expected = logOdds(0.3) + logOdds(0.6);
  REQUIRE(expected < logOdds(p.p_t));
  for (const auto variant : {UpdateVariant::Default, UpdateVariant::Literal}) {
    p.map.variant = variant;
    const LogOddsMap ref = reference::buildMap(set, p);
    REQUIRE(ref.at(v) == expected);
    const auto lib = voxelLogOdds(*KnnInverseSensorModel(p).buildMap(set));
    REQUIRE(lib.at(v) == expected);
    REQUIRE(mapDifferences(ref, lib).empty());
  }
}
