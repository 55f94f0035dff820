// The generator's realism and experiment options (docs/datasets.md, "Realism and experiment options")
// each change only what they say, are deterministic from the seed, and leave the defaults as they were.
#include <cmath>
#include <fstream>
#include <sstream>

#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "occsweep/eval/dataset.hpp"
#include "occsweep/stereo/cloud.hpp"
#include "occsweep/stereo/generate.hpp"
#include "occsweep/stereo/raycast.hpp"
#include "occsweep/stereo/realism.hpp"
#include "test_helpers.hpp"

using namespace occsweep;
using namespace occsweep::stereo;
namespace fs = std::filesystem;

namespace {

/// A tiny generation: 160 x 90 pixels, `keyframes` keyframes (the library accepts any size; the CLI's smallest
/// scale is 320 x 180 with 24).
GenerateConfig tinyConfig(int keyframes = 4) {
  GenerateConfig c;
  c.scale = {"tiny", 160, 90, keyframes, 16, 1};
  return c;
}

Keyframes keyframesOf(const GenerateConfig& c, const std::string& name, std::uint64_t seed = 7) {
  const Scene scene = makeScene(parseDatasetName(name), c.scene);
  return renderKeyframes(scene, zedLikeCamera(c.scale.width, c.scale.height), c, seed);
}

StereoFrame frameOf(const GenerateConfig& c, const std::string& name, std::uint64_t seed = 7) {
  const Scene scene = makeScene(parseDatasetName(name), c.scene);
  const StereoCamera cam = zedLikeCamera(c.scale.width, c.scale.height);
  OrbitConfig orbit;
  orbit.keyframes = 4;
  return renderFrame(scene, cam, orbitPoses(orbit, scene.centre)[0], c.render, seed);
}

bool samePoses(const CameraPose& a, const CameraPose& b) {
  return a.position == b.position && a.rotation == b.rotation;
}

bool sameKeys(const octomap::KeySet& a, const octomap::KeySet& b) {
  if (a.size() != b.size()) return false;
  for (const auto& k : a)
    if (!b.count(k)) return false;
  return true;
}

double rmsDifference(const GreyImage& a, const GreyImage& b) {
  double sum = 0;
  for (std::size_t i = 0; i < a.pixels.size(); ++i) sum += std::pow(double(a.pixels[i]) - b.pixels[i], 2);
  return std::sqrt(sum / double(a.pixels.size()));
}

}  // namespace

TEST_CASE("Pose error leaves the images untouched and moves only the poses the clouds are placed with", "[stereo][realism]") {
  const GenerateConfig plain = tinyConfig();
  GenerateConfig noisy = plain;
  noisy.drift = orbslam2PoseError(plain.scale.keyframes);
  const Keyframes a = keyframesOf(plain, "building-plain-O"), b = keyframesOf(noisy, "building-plain-O");
  REQUIRE(a.frames.size() == b.frames.size());
  for (std::size_t k = 0; k < a.frames.size(); ++k) {
    CHECK(a.frames[k].left.pixels == b.frames[k].left.pixels);
    CHECK(a.frames[k].right.pixels == b.frames[k].right.pixels);
    CHECK(samePoses(a.truth[k], b.truth[k]));
    // The first keyframe defines the map frame; every later one is off its true pose.
    CHECK(samePoses(b.mapping[k], b.truth[k]) == (k == 0));
  }
  // Jitter alone, too, leaves keyframe 0 and moves the others; drift alone is the old random walk, unchanged.
  GenerateConfig jitter_only = plain;
  jitter_only.drift.jitter_metres = 0.01;
  const Keyframes j = keyframesOf(jitter_only, "building-plain-O");
  CHECK(samePoses(j.mapping[0], j.truth[0]));
  CHECK(!samePoses(j.mapping[1], j.truth[1]));
  // Same seed: the same poses; another seed: others.
  const Keyframes again = keyframesOf(noisy, "building-plain-O"), other = keyframesOf(noisy, "building-plain-O", 8);
  for (std::size_t k = 1; k < b.mapping.size(); ++k) {
    CHECK(samePoses(b.mapping[k], again.mapping[k]));
    CHECK(!samePoses(b.mapping[k], other.mapping[k]));
  }
}

TEST_CASE("The orbslam2 preset's RMS position error is ORB-SLAM2's EuRoC median ATE, its rotation the KITTI ratio", "[stereo][realism]") {
  // Expected squared errors over many seeds against the cited figures (docs/datasets.md): position RMS 0.035 m,
  // rotation RMS 0.035 m x (0.23 deg / 0.70 m). Sampling error over 400 seeds is a few per cent.
  for (int keyframes : {24, 144}) {
    OrbitConfig orbit;
    orbit.keyframes = keyframes;
    const auto truth = orbitPoses(orbit, Eigen::Vector3d(0, 0, 0.25));
    PoseDrift drift = orbslam2PoseError(keyframes);
    double position2 = 0, angle2 = 0;
    const int seeds = 400;
    for (int s = 0; s < seeds; ++s) {
      drift.seed = 1000 + s;
      const auto mapped = driftedPoses(truth, drift);
      for (std::size_t k = 0; k < truth.size(); ++k) {
        position2 += (mapped[k].position - truth[k].position).squaredNorm();
        angle2 += std::pow(Eigen::AngleAxisd(mapped[k].rotation * truth[k].rotation.transpose()).angle(), 2);
      }
    }
    const double n = double(seeds) * keyframes;
    INFO("keyframes " << keyframes);
    // Drift's position error also rotates with the yaw walk; a second-order effect at these magnitudes.
    CHECK(std::sqrt(position2 / n) == Approx(kOrbSlam2EurocAteMetres).epsilon(0.06));
    const double deg_per_metre = kOrbSlam2KittiRotDegPer100m / kOrbSlam2KittiTransPercent;
    CHECK(std::sqrt(angle2 / n) * 180 / M_PI == Approx(deg_per_metre * kOrbSlam2EurocAteMetres).epsilon(0.08));
  }
}

TEST_CASE("An exposure difference changes the right image only", "[stereo][realism]") {
  const GenerateConfig plain = tinyConfig();
  GenerateConfig exposed = plain;
  exposed.render.right = exposureMismatchPreset();
  const StereoFrame a = frameOf(plain, "parking-voronoi-L"), b = frameOf(exposed, "parking-voronoi-L");
  CHECK(a.left.pixels == b.left.pixels);
  CHECK(a.target_mask == b.target_mask);
  CHECK(a.right.pixels != b.right.pixels);
  // Vignetting alone darkens the corners and leaves the principal point's pixel as it was (same noise draw).
  GenerateConfig vignetted = plain;
  vignetted.render.right.vignetting = 0.5;
  const StereoFrame v = frameOf(vignetted, "parking-voronoi-L");
  const auto at = [](const GreyImage& img, int u, int y) { return int(img.pixels[std::size_t(y) * img.width + u]); };
  CHECK(at(v.right, 0, 0) < at(a.right, 0, 0));
  CHECK(at(v.right, 159, 89) < at(a.right, 159, 89));
  CHECK(std::abs(at(v.right, 80, 45) - at(a.right, 80, 45)) <= 1);
  CHECK(frameOf(exposed, "parking-voronoi-L").right.pixels == b.right.pixels);  // deterministic
}

TEST_CASE("Far clutter changes pixels only where the sky or the far background was seen, never the truth", "[stereo][realism]") {
  const GenerateConfig plain = tinyConfig();
  GenerateConfig cluttered = plain;
  cluttered.scene.far_clutter = true;
  const StereoFrame a = frameOf(plain, "parking-plain-L"), b = frameOf(cluttered, "parking-plain-L");
  const Scene scene = makeScene(parseDatasetName("parking-plain-L"), plain.scene);
  const Scene scene_cluttered = makeScene(parseDatasetName("parking-plain-L"), cluttered.scene);
  CHECK(sameKeys(sceneGroundTruth(scene, 0.1).occupied, sceneGroundTruth(scene_cluttered, 0.1).occupied));
  CHECK(a.target_mask == b.target_mask);
  // A changed pixel must have a sample ray (the 2 x 2 the renderer casts) that met the sky or ground beyond the
  // nearest clutter ring in the clean scene.
  const StereoCamera cam = zedLikeCamera(160, 90);
  OrbitConfig orbit;
  orbit.keyframes = 4;
  const CameraPose pose = orbitPoses(orbit, scene.centre)[0];
  std::size_t changed = 0;
  for (int v = 0; v < cam.height; ++v)
    for (int u = 0; u < cam.width; ++u) {
      const std::size_t i = std::size_t(v) * cam.width + u;
      if (a.left.pixels[i] == b.left.pixels[i] && a.right.pixels[i] == b.right.pixels[i]) continue;
      changed += 1;
      bool far = false;
      for (const CameraPose& eye : {pose, CameraPose{pose.position + cam.baseline * pose.rotation.col(0), pose.rotation}})
        for (double du : {-0.25, 0.25})
          for (double dv : {-0.25, 0.25}) {
            const Hit hit = castRay(scene, eye.position, pixelRay(cam, eye, u + du, v + dv));
            far = far || hit.surface == Surface::Sky || hit.t > kClutterRings[0] - 1.0;
          }
      INFO("pixel " << u << ", " << v);
      CHECK(far);
    }
  CHECK(changed > 100);
  CHECK(frameOf(cluttered, "parking-plain-L").left.pixels == b.left.pixels);  // deterministic
}

TEST_CASE("Box height moves the box tops and changes the truth when it crosses a voxel boundary", "[stereo][realism]") {
  SceneConfig low, high;
  low.box_height = 0.47;
  high.box_height = 0.55;
  const auto name = parseDatasetName("building-voronoi-T");
  const Scene base = makeScene(name), s47 = makeScene(name, low), s55 = makeScene(name, high);
  for (std::size_t b = 0; b < base.boxes.size(); ++b) {
    CHECK(s47.boxes[b].max[2] == 0.47);
    CHECK(s47.boxes[b].min == base.boxes[b].min);
  }
  CHECK(samePoses(lookAt({3, 0, 1}, s47.centre), lookAt({3, 0, 1}, base.centre)));  // the cameras do not move
  // 0.47 fills the same voxel layers as 0.5 (the top layer [0.4, 0.5] in both); 0.55 adds the layer above.
  const auto t50 = sceneGroundTruth(base, 0.1), t47 = sceneGroundTruth(s47, 0.1), t55 = sceneGroundTruth(s55, 0.1);
  CHECK(sameKeys(t47.occupied, t50.occupied));
  CHECK(t55.occupied.size() > t50.occupied.size());
}

TEST_CASE("Without the voxel filter the cloud has more points, each on its pixel's ray", "[stereo][realism]") {
  const GenerateConfig c = tinyConfig();
  const StereoFrame f = frameOf(c, "building-voronoi-L");
  const StereoCamera cam = zedLikeCamera(160, 90);
  OrbitConfig orbit;
  orbit.keyframes = 4;
  const CameraPose pose = orbitPoses(orbit, makeScene(parseDatasetName("building-voronoi-L")).centre)[0];
  const auto disparity = computeDisparity(f, SgbmParams{}, 16);
  const auto points = reprojectDisparity(disparity, cam, pose, 20.0);
  const auto raw = toPoint3d(points), filtered = voxelFilter(points, 0.1);
  CHECK(2 * raw.size() > 3 * filtered.size());  // at 160 x 90 px about 2x; at ci scale 3.5x (docs)
  std::size_t valid = 0;
  for (auto d : disparity) valid += d > 0 && cam.fx * cam.baseline / (d / 16.0) <= 20.0;
  CHECK(raw.size() == valid);
  for (const auto& p : raw) {
    // Back into the camera: the point projects onto a pixel centre (float storage: well under 0.01 px).
    const Eigen::Vector3d c_p = pose.rotation.transpose() * (Eigen::Vector3d(p.x(), p.y(), p.z()) - pose.position);
    const double u = cam.fx * c_p.x() / c_p.z() + cam.cx, v = cam.fx * c_p.y() / c_p.z() + cam.cy;
    REQUIRE(std::abs(u - std::round(u)) < 0.01);
    REQUIRE(std::abs(v - std::round(v)) < 0.01);
  }
}

TEST_CASE("Noise scale 0, 1, 2: the images move monotonically away from the noiseless one", "[stereo][realism]") {
  GenerateConfig c = tinyConfig();
  const StereoFrame one = frameOf(c, "building-plain-S");
  c.render.noise_scale = 0;
  const StereoFrame zero = frameOf(c, "building-plain-S");
  c.render.noise_scale = 2;
  const StereoFrame two = frameOf(c, "building-plain-S");
  GenerateConfig off = tinyConfig();
  off.render.noise = false;
  CHECK(frameOf(off, "building-plain-S").left.pixels == zero.left.pixels);  // scale 0 is the noiseless image
  const double r1 = rmsDifference(one.left, zero.left), r2 = rmsDifference(two.left, zero.left);
  CHECK(r1 > 0.5);
  CHECK(r2 > 1.6 * r1);  // sigma doubles; 8-bit rounding and clipping keep it below 2x
  CHECK(rmsDifference(two.right, zero.right) > 1.6 * rmsDifference(one.right, zero.right));
  CHECK(frameOf(c, "building-plain-S").left.pixels == two.left.pixels);                 // same seed: same bytes
  CHECK(frameOf(c, "building-plain-S", 8).left.pixels != two.left.pixels);              // another seed: others
}

TEST_CASE("Every option at its default value changes no byte, and options used are recorded", "[stereo][realism][cli]") {
  const fs::path a = test::scratch("stereo-realism-a"), b = test::scratch("stereo-realism-b"),
                 r = test::scratch("stereo-realism-r");
  const std::string common = " dataset generate --name parking-plain-O --scale ci --pcs 0 --no-preview --out ";
  REQUIRE(test::runCli(common + a.string()).exit_code == 0);
  REQUIRE(test::runCli(common + b.string() + " --pose-jitter 0 --rot-jitter 0 --right-gain 1 --right-offset 0 "
                       "--right-gamma 1 --right-vignetting 0 --box-height 0.5 --noise-scale 1").exit_code == 0);
  const auto files = test::filesUnder(a);
  REQUIRE(files == test::filesUnder(b));
  for (const auto& f : files) {
    INFO(f);
    CHECK(test::bytesOf(a / f) == test::bytesOf(b / f));
  }
  const fs::path set = fs::path("parking-plain-O") / "pcs-0000";
  const Dataset plain = readDataset(a / set);
  CHECK(!plain.source.contains("options"));
  CHECK(!nlohmann::json::parse(test::bytesOf(a / "parking-plain-O" / "ranking.json")).contains("options"));

  REQUIRE(test::runCli(common + r.string() + " --realistic --no-voxel-filter").exit_code == 0);
  const Dataset real = readDataset(r / set);
  const auto options = real.source["options"];
  CHECK(options["realistic"] == true);
  CHECK(options["pose_error"]["preset"] == "orbslam2");
  CHECK(options["right_exposure"]["preset"] == "mismatch");
  CHECK(options["far_clutter"] == true);
  CHECK(options["voxel_filter"] == false);
  CHECK(!options.contains("noise_scale"));
  CHECK(nlohmann::json::parse(test::bytesOf(r / "parking-plain-O" / "ranking.json"))["options"] == options);
  CHECK(real.truth.boxes.size() == plain.truth.boxes.size());
  for (std::size_t i = 0; i < plain.truth.boxes.size(); ++i) {
    CHECK(real.truth.boxes[i].min == plain.truth.boxes[i].min);
    CHECK(real.truth.boxes[i].max == plain.truth.boxes[i].max);
  }
  CHECK(pointCount(real.scans) > pointCount(plain.scans));  // unfiltered
}

TEST_CASE("Bad realism values are refused with the flag and the rule, and write nothing", "[stereo][realism][cli]") {
  const fs::path out = test::scratch("stereo-realism-bad") / "out";
  auto refused = [&](const std::string& args, const std::string& message) {
    const auto r = test::runCli(" dataset generate --name building-plain-L --out " + out.string() + " " + args);
    INFO(args << "\n" << r.output);
    CHECK(r.exit_code == 2);
    CHECK(r.output.find(message) != std::string::npos);
    CHECK(!fs::exists(out));
  };
  refused("--noise-scale -1", "--noise-scale must be a number in [0, 10]");
  refused("--box-height 0", "--box-height must be a number in (0, 1]");
  refused("--right-vignetting 1.5", "--right-vignetting must be a number in [0, 1]");
  refused("--right-gain 0", "--right-gain must be a number in (0, 10]");
  refused("--pose-jitter -0.1", "--pose-jitter must be a number in [0, 1]");
  refused("--pose-error kitti", "--pose-error");
  refused("--exposure bright", "--exposure");
  refused("--pose-error orbslam2 --pose-jitter 0.01", "--pose-jitter");
  refused("--exposure mismatch --right-gain 2", "--right-gain");
  refused("--realistic --pose-drift 0.01", "--pose-drift");
}

TEST_CASE("Drift alone is recorded too: reproduce tells data sets apart by the recorded options", "[stereo][realism]") {
  GenerateConfig c;
  CHECK(realismOptionsJson(c).empty());
  c.drift.metres_per_keyframe = 0.01;
  c.drift.yaw_deg_per_keyframe = 0.2;
  const auto options = realismOptionsJson(c);
  REQUIRE(options.contains("pose_error"));
  CHECK(options["pose_error"]["drift_metres_per_keyframe"] == 0.01);
  CHECK(options["pose_error"]["drift_yaw_deg_per_keyframe"] == 0.2);
  CHECK(options["pose_error"]["preset"] == "");
}
