// Observable truth with the scans' views (docs/results-format.md, "Truth"; docs/dataset-format.md, "Sensor views"):
// a depth camera sees its image, a range sensor its cone. Hand-built scenes whose answer is known, a property test
// against a plain oracle (liboctomap's computeRayKeys and the projection written out again), the built-in scene's
// recorded camera against its own rays, and the views through the manifest.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>

#include <octomap/OcTree.h>

#include "occsweep/core/splitmix64.hpp"
#include "occsweep/eval/builtin_scene.hpp"
#include "occsweep/io/data_error.hpp"
#include "occsweep/eval/observable_truth.hpp"
#include "test_helpers.hpp"

using namespace occsweep;
namespace fs = std::filesystem;
using octomap::point3d;

namespace {

constexpr double kResolution = 0.1;

GroundTruth truthOfBoxes(const std::vector<AxisBox>& boxes) {
  TruthSources sources;
  sources.boxes = boxes;
  return makeGroundTruth(sources, AxisBox{{-1.0, -2.0, -1.0}, {4.0, 2.0, 2.0}}, kResolution);
}

GroundTruth truthOfBox(const AxisBox& box) { return truthOfBoxes({box}); }

const point3d kOrigin(0.05f, 0.03f, 0.51f);

// A 64 x 48 depth camera, fx = fy = 50 (about 65 degrees across), at kOrigin looking along world +x: camera x
// (right) is world -y, camera y (down) world -z.
PinholeView cameraAlongX() {
  return PinholeView{50, 50, 31.5, 23.5, 64, 48, {0, 0, 1, -1, 0, 0, 0, -1, 0}};
}

// A wall 2 m ahead, wider and higher than the image; a box in the image, in front of the wall; a box beside the
// camera, 75 degrees off its axis and 1 m away: outside the image (and any 30-degree cone along +x).
const AxisBox kWall{{2.02, -1.98, -0.98}, {2.08, 1.98, 1.98}};
const AxisBox kBoxInImage{{1.22, 0.12, 0.42}, {1.38, 0.28, 0.58}};
const AxisBox kBoxBeside{{0.22, 0.92, 0.42}, {0.38, 1.08, 0.58}};

std::size_t seenCount(const AxisBox& box, const SensorView& view) {
  return observableTruthVoxels(truthOfBox(box), std::vector<Viewpoint>{{kOrigin, view}}, 4.0).size();
}

// The oracle's view test, from the definitions alone: the camera frame by R^T, the pixel, the image's pixel
// rectangle; the cone by the angle between two vectors.
bool oracleInView(const SensorView& view, const point3d& origin, const point3d& p) {
  const double d[3] = {double(p.x()) - origin.x(), double(p.y()) - origin.y(), double(p.z()) - origin.z()};
  if (const auto* c = std::get_if<PinholeView>(&view)) {
    double cam[3] = {0, 0, 0};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) cam[i] += c->rotation[std::size_t(3 * j + i)] * d[j];
    if (cam[2] <= 0) return false;
    const double u = c->cx + c->fx * cam[0] / cam[2], v = c->cy + c->fy * cam[1] / cam[2];
    return -0.5 <= u && u <= c->width - 0.5 && -0.5 <= v && v <= c->height - 0.5;
  }
  if (const auto* c = std::get_if<ConeView>(&view)) {
    if (c->half_angle_deg == 180) return true;
    const double dot = c->axis[0] * d[0] + c->axis[1] * d[1] + c->axis[2] * d[2];
    const double a = std::hypot(c->axis[0], c->axis[1], c->axis[2]), b = std::hypot(d[0], d[1], d[2]);
    return b > 0 && std::acos(std::clamp(dot / (a * b), -1.0, 1.0)) <= c->half_angle_deg * M_PI / 180.0 + 1e-12;
  }
  return true;
}

// test_observable_truth.cpp's oracle with the view: an aim point counts only inside the view, except in the
// origin's own voxel.
octomap::KeySet oracleObservable(const GroundTruth& truth, const std::vector<Viewpoint>& viewpoints, double s_c) {
  octomap::OcTree tree(truth.resolution);
  const float inside = float(0.49 * truth.resolution);
  const point3d offsets[7] = {{0, 0, 0},       {inside, 0, 0}, {-inside, 0, 0}, {0, inside, 0},
                              {0, -inside, 0}, {0, 0, inside}, {0, 0, -inside}};
  octomap::KeyRay ray;  // allocated once: a KeyRay holds room for 100,000 keys
  octomap::KeySet seen;
  for (const auto& key : truth.occupied) {
    const point3d centre = tree.keyToCoord(key);
    for (const auto& [origin, view] : viewpoints) {
      if (!((centre - origin).norm() <= s_c)) continue;
      for (const point3d& offset : offsets) {
        const point3d aim = centre + offset;
        if (tree.coordToKey(aim) != key || !tree.computeRayKeys(origin, aim, ray)) continue;
        if (tree.coordToKey(origin) != key && !oracleInView(view, origin, aim)) continue;
        bool blocked = false;
        for (const auto& k : ray) blocked = blocked || truth.occupied.count(k) > 0;
        if (!blocked) seen.insert(key);
      }
    }
  }
  return seen;
}

std::vector<std::array<int, 3>> sorted(const octomap::KeySet& keys) {
  std::vector<std::array<int, 3>> v;
  for (const auto& k : keys) v.push_back({k[0], k[1], k[2]});
  std::sort(v.begin(), v.end());
  return v;
}

// A rotation from a random unit quaternion, row-major.
std::array<double, 9> randomRotation(SplitMix64& rng) {
  double q[4] = {rng.gaussian(), rng.gaussian(), rng.gaussian(), rng.gaussian()};
  const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  const double w = q[0] / n, x = q[1] / n, y = q[2] / n, z = q[3] / n;
  return {1 - 2 * (y * y + z * z), 2 * (x * y - w * z),     2 * (x * z + w * y),
          2 * (x * y + w * z),     1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
          2 * (x * z - w * y),     2 * (y * z + w * x),     1 - 2 * (x * x + y * y)};
}

SensorView randomView(SplitMix64& rng) {
  switch (rng.below(3)) {
    case 0:
      return PinholeView{20 + 80 * rng.uniform(), 20 + 80 * rng.uniform(), 10 + 40 * rng.uniform(),
                         10 + 30 * rng.uniform(), 16 + int(rng.below(64)), 12 + int(rng.below(48)), randomRotation(rng)};
    case 1:
      return ConeView{{rng.gaussian(), rng.gaussian(), rng.gaussian()}, 5 + 175 * rng.uniform()};
    default:
      return SphereView{};
  }
}

}  // namespace

TEST_CASE("a depth camera facing a wall sees the box in its image, not the box beside it 75 degrees off its axis") {
  const SensorView camera = cameraAlongX();
  CHECK(seenCount(kBoxBeside, camera) == 0);
  CHECK(seenCount(kBoxBeside, SphereView{}) > 0);  // every direction: seen, as before views were recorded
  CHECK(seenCount(kBoxInImage, camera) == seenCount(kBoxInImage, SphereView{}));
  CHECK(seenCount(kBoxInImage, camera) > 0);
  // With the wall: the box beside adds nothing; the wall is seen only where the image reaches it (65 x 51 degrees
  // across: 2.56 x 1.92 m at 2 m of a 4 x 3 m wall), never beyond.
  const std::vector<Viewpoint> from{{kOrigin, camera}};
  const GroundTruth scene = truthOfBoxes({kWall, kBoxInImage, kBoxBeside});
  const octomap::KeySet seen = observableTruthVoxels(scene, from, 4.0);
  CHECK(sorted(seen) == sorted(observableTruthVoxels(truthOfBoxes({kWall, kBoxInImage}), from, 4.0)));
  const std::size_t wall = truthOfBox(kWall).occupied.size(), wall_seen = seenCount(kWall, camera);
  CHECK(wall_seen > wall / 3);
  CHECK(wall_seen < wall / 2);
}

TEST_CASE("a range sensor's cone sees the box inside it, not the box outside, and 180 degrees is every direction") {
  const ConeView cone{{1, 0, 0}, 30};
  CHECK(seenCount(kBoxInImage, cone) > 0);
  CHECK(seenCount(kBoxBeside, cone) == 0);
  CHECK(seenCount(kBoxBeside, ConeView{{1, 0, 0}, 80}) > 0);  // 75 degrees off the axis: inside an 80-degree cone
  CHECK(seenCount(kBoxBeside, ConeView{{-1, 0, 0}, 180}) == seenCount(kBoxBeside, SphereView{}));
}

TEST_CASE("an origin inside a truth voxel sees that voxel whatever its view, and nothing behind its camera") {
  const GroundTruth truth = truthOfBoxes({AxisBox{{0.02, -0.08, 0.42}, {0.08, 0.08, 0.58}}, kWall});
  const PinholeView backwards{50, 50, 31.5, 23.5, 64, 48, {0, 0, -1, 1, 0, 0, 0, -1, 0}};  // looking along -x
  const octomap::OcTree grid(kResolution);
  const octomap::OcTreeKey own = grid.coordToKey(kOrigin);
  CHECK(sorted(observableTruthVoxels(truth, std::vector<Viewpoint>{{kOrigin, backwards}}, 4.0)) ==
        std::vector<std::array<int, 3>>{{own[0], own[1], own[2]}});
  CHECK(observableTruthVoxels(truthOfBox(kWall), std::vector<Viewpoint>{{kOrigin, backwards}}, 4.0).empty());
}

TEST_CASE("observable truth with views equals the oracle on 60 random scenes of cameras, cones and spheres") {
  std::size_t seen_total = 0, hidden_total = 0, cut_by_view = 0;
  for (std::uint64_t seed = 1; seed <= 60; ++seed) {
    SplitMix64 rng(seed);
    std::vector<AxisBox> boxes;
    for (std::size_t b = 0, n = 1 + rng.below(4); b < n; ++b) {
      AxisBox box;
      for (int i = 0; i < 3; ++i) box.min[i] = -0.5 + 2.0 * rng.uniform(), box.max[i] = box.min[i] + 0.05 + 0.5 * rng.uniform();
      boxes.push_back(box);
    }
    std::vector<Viewpoint> viewpoints;
    std::vector<point3d> origins;
    for (std::size_t o = 0, n = 1 + rng.below(5); o < n; ++o) {
      origins.emplace_back(float(-0.9 + 3.5 * rng.uniform()), float(-1.5 + 3.0 * rng.uniform()),
                           float(-0.5 + 2.0 * rng.uniform()));
      viewpoints.push_back({origins.back(), randomView(rng)});
    }
    const double s_c = 0.5 + 3.0 * rng.uniform();
    const GroundTruth truth = truthOfBoxes(boxes);
    INFO("seed " << seed << ", " << truth.occupied.size() << " truth voxels, " << viewpoints.size() << " viewpoints");
    const octomap::KeySet seen = observableTruthVoxels(truth, viewpoints, s_c);
    CHECK(sorted(seen) == sorted(oracleObservable(truth, viewpoints, s_c)));
    seen_total += seen.size(), hidden_total += truth.occupied.size() - seen.size();
    cut_by_view += observableTruthVoxels(truth, origins, s_c).size() - seen.size();
  }
  CHECK(seen_total > 100);
  CHECK(hidden_total > 100);
  CHECK(cut_by_view > 100);  // the views matter in these scenes
}

TEST_CASE("the built-in scene records each scan's camera: every point lies in its image, and nothing seen is lost") {
  const Dataset d = makeBuiltinScene();
  for (const Scan& scan : d.scans) {
    REQUIRE(scan.view);
    const auto* camera = std::get_if<PinholeView>(&*scan.view);
    REQUIRE(camera);
    CHECK(camera->width == 64);
    CHECK(camera->height == 48);
    CHECK(!brokenViewRule(*scan.view));
    for (const point3d& p : scan.points) REQUIRE(oracleInView(*scan.view, scan.origin, p));
  }
  // The boxes fill about a quarter of each image: the views leave the observable truth as it was (241 of 484).
  const GroundTruth truth = makeGroundTruth(d.truth, d.region, kResolution);
  std::vector<point3d> origins;
  for (const Scan& scan : d.scans) origins.push_back(scan.origin);
  const octomap::KeySet with_views = observableTruthVoxels(truth, viewpointsOf(d.scans), 4.0);
  CHECK(with_views.size() == 241);
  CHECK(sorted(with_views) == sorted(observableTruthVoxels(truth, origins, 4.0)));
}

TEST_CASE("views go through the manifest unchanged, a data set without them reads as before, bad views are refused") {
  const fs::path dir = test::scratch("observable-views-manifest");
  Dataset d = makeBuiltinScene({.seed = 2, .scans = 3, .width = 16, .height = 12});
  d.scans[1].view = ConeView{{0.3, -0.2, 0.9}, 42.5};
  d.scans[2].view = SphereView{};
  writeDataset(d, dir / "views");
  const Dataset back = readDataset(dir / "views");
  REQUIRE(back.scans.size() == 3);
  const auto& camera = std::get<PinholeView>(*back.scans[0].view);
  const auto& written = std::get<PinholeView>(*d.scans[0].view);
  CHECK(camera.rotation == written.rotation);
  CHECK(camera.fx == written.fx);
  CHECK(camera.cx == 7.5);
  CHECK(std::get<ConeView>(*back.scans[1].view).axis == std::array<double, 3>{0.3, -0.2, 0.9});
  CHECK(std::holds_alternative<SphereView>(*back.scans[2].view));
  for (Scan& s : d.scans) s.view.reset();
  writeDataset(d, dir / "none");
  CHECK(test::bytesOf(dir / "none" / "manifest.json").find("\"view\"") == std::string::npos);
  for (const Scan& s : readDataset(dir / "none").scans) CHECK(!s.view);

  auto refused = [&](const std::string& name, const nlohmann::json& view, const std::string& field) {
    auto m = nlohmann::json::parse(std::ifstream(dir / "views" / "manifest.json"));
    m["scans"][0]["view"] = view;
    fs::copy(dir / "views", dir / name, fs::copy_options::recursive);
    std::ofstream(dir / name / "manifest.json") << m.dump(1);
    INFO(name);
    CHECK_THROWS_WITH(readDataset(dir / name),
                      Catch::Contains((dir / name / "manifest.json").string()) && Catch::Contains(field));
  };
  auto pinhole = nlohmann::json::parse(std::ifstream(dir / "views" / "manifest.json"))["scans"][0]["view"];
  auto with = [](nlohmann::json j, const char* key, const nlohmann::json& value) { j[key] = value; return j; };
  refused("negative-fx", with(pinhole, "fx", -50), "scans[0].view.fx: must be a finite number > 0");
  refused("no-height", [&] { auto j = pinhole; j.erase("height"); return j; }(), "scans[0].view.height: field is missing");
  refused("zero-width", with(pinhole, "width", 0), "scans[0].view.width");
  refused("reflection", with(pinhole, "rotation", {-1, 0, 0, 0, 1, 0, 0, 0, 1}), "scans[0].view.rotation");
  refused("wide-cone", {{"model", "cone"}, {"axis", {0, 0, 1}}, {"half_angle_deg", 181}},
          "scans[0].view.half_angle_deg: must be in (0, 180]");
  refused("flat-cone", {{"model", "cone"}, {"axis", {0, 0, 1}}, {"half_angle_deg", 0}}, "scans[0].view.half_angle_deg");
  refused("zero-axis", {{"model", "cone"}, {"axis", {0, 0, 0}}, {"half_angle_deg", 30}}, "scans[0].view.axis");
  refused("fisheye", {{"model", "fisheye"}}, "scans[0].view.model");
}
