// Both mappers on hand-built rays (exact log-odds per voxel), the literal/default variants, and the
// equivalence property: the k-NN mapper reduces to liboctomap when p_u = p_l = p_h, p'_m = p_m and every
// voxel of a scan holds one point.
#include <catch2/catch.hpp>

#include <cmath>

#include "occsweep/methods/knn/knn_inverse_sensor_model.hpp"
#include "occsweep/core/map_voxels.hpp"
#include "occsweep/methods/octomap/octomap_baseline.hpp"
#include "occsweep/core/voxel_update_rule.hpp"
#include "test_helpers.hpp"

using namespace occsweep;
using octomap::OcTreeKey;

namespace {

constexpr int kZero = 32768;  // OctoMap's key of the voxel [0, 0.1) at 0.1 m

// Log-odds of the voxel whose x index is `x` (y, z in the first voxel); NaN when unknown.
float at(const octomap::OcTree& t, int x) {
  const auto* n = t.search(OcTreeKey(kZero + x, kZero, kZero));
  return n ? n->getLogOdds() : NAN;
}

// Every leaf of the tree: a voxel the hand-built cases do not list would show here. (One row of voxels along x
// never has eight equal siblings, so nothing is pruned and each leaf is one voxel.)
std::size_t leafCount(const octomap::OcTree& t) {
  std::size_t n = 0;
  for (auto it = t.begin_leafs(), end = t.end_leafs(); it != end; ++it) ++n;
  return n;
}

float lo(double p) { return float(std::log(p / (1.0 - p))); }  // Eq. 2, by hand

Scan lineScan(std::vector<octomap::point3d> pts) { return Scan{{0.05f, 0.05f, 0.05f}, std::move(pts), {}}; }

}  // namespace

TEST_CASE("OctoMap baseline on one hand-built ray: free voxels, the hit voxel, clamping") {
  OctoMapParams p;  // p_h 0.7, p_m 0.4, p_max 0.97, p_min 0.12
  const PointCloudSet one = {lineScan({{0.55f, 0.05f, 0.05f}})};
  auto t = buildOctoMap(one, p);
  for (int x = 0; x <= 4; ++x) CHECK(at(*t, x) == lo(0.4));  // origin voxel included
  CHECK(at(*t, 5) == lo(0.7));                                // end voxel hit, not freed
  CHECK(std::isnan(at(*t, 6)));
  CHECK(leafCount(*t) == 6);  // voxels 0 to 5 and nothing else
  const PointCloudSet ten(10, one[0]);
  auto t10 = buildOctoMap(ten, p);
  CHECK(at(*t10, 5) == lo(0.97));  // clamped at l_max (Eq. 5)
  CHECK(at(*t10, 0) == lo(0.12));  // clamped at l_min
}

TEST_CASE("k-NN model on hand-built rays: summed hits, l_in, l_out, default and literal") {
  // A and A2 share a voxel; B lies behind A on the same ray; C is beyond s_c = 4 on that ray.
  const octomap::point3d A{0.55f, 0.05f, 0.05f}, A2{0.58f, 0.06f, 0.04f}, B{0.95f, 0.05f, 0.05f},
      C{5.05f, 0.05f, 0.05f};
  const PointCloudSet set = {lineScan({A, A2, B, C})};
  KnnParams p;
  p.k = 1;
  p.p_u = 0.9, p.p_l = 0.3, p.p_m = 0.3, p.p_m_out = 0.45, p.p_max = 0.97, p.p_min = 0.12;
  // By hand: k = 1 nearest others within z_in = {A, A2, B}.
  auto dist = [](const octomap::point3d& a, const octomap::point3d& b) {
    return std::sqrt(std::pow(double(a.x()) - b.x(), 2) + std::pow(double(a.y()) - b.y(), 2) +
                     std::pow(double(a.z()) - b.z(), 2));
  };
  const double sA = dist(A, A2), sA2 = sA, sB = dist(B, A2);
  const double mu = (sA + sA2 + sB) / 3.0;
  const double sigma = std::sqrt((std::pow(sA - mu, 2) + std::pow(sA2 - mu, 2) + std::pow(sB - mu, 2)) / 3.0);
  auto l_of = [&](double s) {
    const double F = 0.5 * std::erfc(-(s - mu) / (sigma * std::sqrt(2.0)));
    return lo(0.9 - F * (0.9 - 0.3));
  };
  const float hitA = std::min(std::max(l_of(sA) + l_of(sA2), lo(0.12)), lo(0.97));
  const float hitB = l_of(sB);
  const int keyA = 5, keyB = 9, keyCut = 40;  // x = 0.05 + 4.0 = 4.05 -> voxel 40, excluded

  SECTION("default: occupied wins") {
    auto t = KnnInverseSensorModel(p).buildMap(set);
    for (int x = 0; x < keyA; ++x) CHECK(at(*t, x) == lo(0.3));
    CHECK(at(*t, keyA) == hitA);
    for (int x = keyA + 1; x < keyB; ++x) CHECK(at(*t, x) == lo(0.3));  // crossed by the ray to B
    CHECK(at(*t, keyB) == hitB);                                         // on the ray to C, but holds B
    for (int x = keyB + 1; x < keyCut; ++x) CHECK(at(*t, x) == lo(0.45));  // only the cut ray to C: l_out
    CHECK(std::isnan(at(*t, keyCut)));
    CHECK(leafCount(*t) == std::size_t(keyCut));  // voxels 0 to 39 and nothing else
  }
  SECTION("literal: Algorithm 1 word for word, hits then l_in then l_out") {
    p.map.variant = UpdateVariant::Literal;
    auto t = KnnInverseSensorModel(p).buildMap(set);
    CHECK(at(*t, keyA) == hitA + lo(0.3));  // A's voxel is crossed by the ray to B
    CHECK(at(*t, keyB) == hitB + lo(0.45)); // B's voxel is crossed only by the ray to C
  }
  SECTION("online statistics use the running mu and sigma of the scans so far") {
    PointCloudSet two = {lineScan({A, A2, B}), lineScan({A, B})};
    p.map.stats = StatsMode::Online;
    const auto d = computeKnnDistances(two, 1, 4.0);
    CHECK(d.scans[0].online_mu == Approx(mu));
    CHECK(d.scans[1].online_mu == Approx((sA + sA2 + sB + 2 * dist(A, B)) / 5.0));
    CHECK(d.mu == Approx(d.scans[1].online_mu));
  }
}

TEST_CASE("k-NN mapper equals liboctomap voxel for voxel when p_u = p_l = p_h, p'_m = p_m, one point per voxel") {
  for (std::uint64_t seed = 1; seed <= 25; ++seed) {
    SplitMix64 rng(seed);
    const double probs[] = {0.5, 0.62, 0.74, 0.86, 0.98};
    const double misses[] = {0.02, 0.14, 0.26, 0.38};
    OctoMapParams om;
    om.p_max = 0.98 - 0.12 * double(rng.below(2));
    om.p_h = std::min(probs[rng.below(5)], om.p_max);
    om.p_m = misses[rng.below(4)];
    om.p_min = std::min(0.02 + 0.12 * double(rng.below(4)), om.p_m);
    om.map.s_c = 2.0 + rng.uniform() * 2.0;
    PointCloudSet set;
    const int scans = 2 + int(rng.below(6));
    for (int s = 0; s < scans; ++s) {
      Scan scan;
      scan.origin = octomap::point3d(float(rng.uniform() - 0.5), float(rng.uniform() - 0.5), float(rng.uniform()));
      octomap::OcTree grid(om.map.resolution);
      octomap::KeySet used;
      for (int i = 0; i < 400; ++i) {
        const octomap::point3d p(float((rng.uniform() - 0.5) * 10), float((rng.uniform() - 0.5) * 10),
                                 float(rng.uniform() * 2));
        if (used.insert(grid.coordToKey(p)).second) scan.points.push_back(p);  // one point per voxel
      }
      set.push_back(scan);
    }
    KnnParams kp;
    kp.p_u = kp.p_l = om.p_h;
    kp.p_m = kp.p_m_out = om.p_m;
    kp.p_max = om.p_max, kp.p_min = om.p_min, kp.p_t = om.p_min, kp.map.s_c = om.map.s_c, kp.k = 1 + int(rng.below(5));
    const auto reference = voxelLogOdds(*buildOctoMap(set, om));
    const auto ours = voxelLogOdds(*KnnInverseSensorModel(kp).buildMap(set));
    INFO("seed " << seed);
    REQUIRE(reference.size() > 1000);
    REQUIRE(ours.size() == reference.size());
    std::size_t differing = 0;
    for (const auto& [key, value] : reference) {
      auto it = ours.find(key);
      if (it == ours.end() || it->second != value) ++differing;
    }
    REQUIRE(differing == 0);
  }
}

TEST_CASE("with several points in a voxel the two mappers differ (the property above is not vacuous)") {
  const PointCloudSet set = {lineScan({{0.55f, 0.05f, 0.05f}, {0.56f, 0.05f, 0.05f}})};
  OctoMapParams om;
  KnnParams kp;
  kp.p_u = kp.p_l = om.p_h;
  kp.p_m = kp.p_m_out = om.p_m;
  kp.p_max = om.p_max, kp.p_min = om.p_min;
  CHECK(at(*buildOctoMap(set, om), 5) == lo(0.7));
  CHECK(at(*KnnInverseSensorModel(kp).buildMap(set), 5) == lo(0.7) + lo(0.7));
}

TEST_CASE("the k-NN fast build equals the plain OcTree-update reference voxel for voxel") {
  for (std::uint64_t seed = 100; seed < 124; ++seed) {
    SplitMix64 rng(seed);
    KnnParams p;
    p.k = 1 + int(rng.below(6));
    p.p_u = 0.5 + 0.45 * rng.uniform();
    p.p_l = 0.05 + (p.p_u - 0.05) * rng.uniform();
    p.p_min = 0.02 + 0.2 * rng.uniform();
    p.p_m = p.p_min + (0.45 - p.p_min) * rng.uniform();
    p.p_m_out = p.p_m + (0.49 - p.p_m) * rng.uniform();
    p.p_max = 0.6 + 0.39 * rng.uniform();
    p.p_t = p.p_min;
    p.map.s_c = 1.5 + 2.5 * rng.uniform();
    p.map.variant = rng.below(2) ? UpdateVariant::Literal : UpdateVariant::Default;
    p.map.stats = rng.below(2) ? StatsMode::Online : StatsMode::Batch;
    PointCloudSet set;
    for (int s = 0; s < 3 + int(rng.below(5)); ++s) {
      Scan scan;
      scan.origin = octomap::point3d(float(rng.uniform() - 0.5), float(rng.uniform() - 0.5), float(rng.uniform()));
      // Clustered points (several per voxel) and scattered ones, some beyond s_c.
      for (int c = 0; c < 30; ++c) {
        const octomap::point3d centre(float((rng.uniform() - 0.5) * 8), float((rng.uniform() - 0.5) * 8),
                                      float(rng.uniform() * 2));
        for (int i = 0; i < 1 + int(rng.below(12)); ++i)
          scan.points.push_back(centre + octomap::point3d(float(rng.gaussian() * 0.05), float(rng.gaussian() * 0.05),
                                                          float(rng.gaussian() * 0.05)));
      }
      set.push_back(scan);
    }
    const KnnInverseSensorModel model(p);
    const auto d = computeKnnDistances(set, p.k, p.map.s_c);
    const auto fast = voxelLogOdds(*model.buildMap(set, d));
    const auto reference = voxelLogOdds(*model.buildMapReference(set, d));
    INFO("seed " << seed << (p.map.variant == UpdateVariant::Literal ? " literal" : " default")
                 << (p.map.stats == StatsMode::Online ? " online" : " batch"));
    REQUIRE(reference.size() > 500);
    REQUIRE(fast.size() == reference.size());
    std::size_t differing = 0;
    for (const auto& [key, value] : reference) {
      auto it = fast.find(key);
      if (it == fast.end() || it->second != value) ++differing;
    }
    REQUIRE(differing == 0);
  }
}

TEST_CASE("the voxel update rule: hit first, then l_in, else l_out, and the default stops after a hit") {
  // Each update recorded as its delta, in order; the hit's delta is 9 so that it is told apart.
  auto updates = [](UpdateVariant variant, std::uint8_t flags) {
    const VoxelUpdateRule<float> rule{-1.0f, -2.0f, variant};
    std::vector<float> applied;
    rule.apply(flags, [] { return 9.0f; }, [&](float delta) { applied.push_back(delta); });
    return applied;
  };
  using V = std::vector<float>;
  for (const UpdateVariant variant : {UpdateVariant::Default, UpdateVariant::Literal}) {
    INFO(toText(variant));
    const bool literal = variant == UpdateVariant::Literal;
    CHECK(updates(variant, 0) == V{});
    CHECK(updates(variant, kHit) == V{9});
    CHECK(updates(variant, kCrossedIn) == V{-1});
    CHECK(updates(variant, kCrossedOut) == V{-2});
    CHECK(updates(variant, kCrossedIn | kCrossedOut) == V{-1});  // l_out only where no ray to z_in passed
    CHECK(updates(variant, kHit | kCrossedIn) == (literal ? V{9, -1} : V{9}));
    CHECK(updates(variant, kHit | kCrossedOut) == (literal ? V{9, -2} : V{9}));
    CHECK(updates(variant, kHit | kCrossedIn | kCrossedOut) == (literal ? V{9, -1} : V{9}));
  }
  // The hit's delta (a sum over the voxel's points) is computed only for a hit voxel.
  const VoxelUpdateRule<float> rule{-1.0f, -2.0f, UpdateVariant::Literal};
  int computed = 0;
  rule.apply(kCrossedIn | kCrossedOut, [&] { return float(++computed); }, [](float) {});
  CHECK(computed == 0);
}
