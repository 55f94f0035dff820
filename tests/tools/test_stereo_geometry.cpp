// The renderer's geometry, the stereo reprojection and the scene's ground truth against independent
// oracles (face-plane intersection, hand-counted voxels).
#include <algorithm>
#include <cmath>
#include <limits>

#include <catch2/catch.hpp>

#include "occsweep/core/splitmix64.hpp"
#include "occsweep/stereo/cloud.hpp"
#include "occsweep/stereo/render.hpp"

using namespace occsweep;
using namespace occsweep::stereo;

namespace {

// Oracle: nearest intersection of a ray with the six face rectangles of a box (not the slab test).
double faceIntersection(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const AxisBox& b) {
  double best = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a)
    for (double plane : {b.min[a], b.max[a]}) {
      if (d[a] == 0) continue;
      const double t = (plane - o[a]) / d[a];
      if (t <= 0) continue;
      const Eigen::Vector3d p = o + t * d;
      bool inside = true;
      for (int c = 0; c < 3; ++c)
        if (c != a && (p[c] < b.min[c] - 1e-12 || p[c] > b.max[c] + 1e-12)) inside = false;
      if (inside) best = std::min(best, t);
    }
  return best;
}

// Oracle: distance from p to the surface of the nearest box (inside or outside).
double boxSurfaceDistance(const std::vector<AxisBox>& boxes, const Eigen::Vector3d& p) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& b : boxes) {
    double out2 = 0, in = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a) {
      const double gap = std::max({b.min[a] - p[a], p[a] - b.max[a], 0.0});
      out2 += gap * gap;
      in = std::min(in, std::min(p[a] - b.min[a], b.max[a] - p[a]));
    }
    best = std::min(best, out2 > 0 ? std::sqrt(out2) : in);
  }
  return best;
}

StereoCamera smallCamera() { return zedLikeCamera(96, 54); }

}  // namespace

TEST_CASE("A rendered pixel's depth equals the analytic ray-box distance", "[stereo][render]") {
  RenderConfig config;
  config.supersample = 1;
  const StereoCamera cam = smallCamera();
  for (const DatasetName& name : allDatasetNames()) {
    const Scene scene = makeScene(name);
    SplitMix64 rng(std::hash<std::string>{}(name.str()) | 1);
    for (int trial = 0; trial < 3; ++trial) {
      const double angle = 2 * M_PI * rng.uniform(), radius = 1.8 + 1.5 * rng.uniform(), h = 0.6 + rng.uniform();
      const Eigen::Vector3d eye = scene.centre + Eigen::Vector3d(radius * std::cos(angle), radius * std::sin(angle), h);
      const CameraPose pose = lookAt(eye, scene.centre);
      const StereoFrame f = renderFrame(scene, cam, pose, config, rng.next());
      int box_pixels = 0;
      for (int v = 0; v < cam.height; ++v)
        for (int u = 0; u < cam.width; ++u) {
          const std::size_t i = std::size_t(v) * cam.width + u;
          const Eigen::Vector3d dir = pixelRay(cam, pose, u, v);
          double t = std::numeric_limits<double>::infinity();
          for (const auto& b : scene.boxes) t = std::min(t, faceIntersection(eye, dir, b));
          const double ground = dir.z() < 0 ? -eye.z() / dir.z() : std::numeric_limits<double>::infinity();
          const bool box_first = t < ground;
          REQUIRE(bool(f.target_mask[i]) == box_first);
          if (!box_first) continue;
          ++box_pixels;
          const double z = t * dir.dot(pose.rotation.col(2));
          REQUIRE(f.left_depth[i] == Approx(z).epsilon(1e-6));
        }
      CHECK(box_pixels > 50);  // the camera looks at the targets
    }
  }
}

TEST_CASE("Reprojecting a rendered ground-truth disparity returns the box surface within one voxel", "[stereo]") {
  RenderConfig config;
  config.supersample = 1;
  const StereoCamera cam = zedLikeCamera(320, 180);
  for (Layout layout : {Layout::I, Layout::O, Layout::T, Layout::L, Layout::S}) {
    const Scene scene = makeScene({Environment::Parking, Texture::Voronoi, layout});
    OrbitConfig orbit;
    orbit.keyframes = 6;
    for (const CameraPose& pose : orbitPoses(orbit, scene.centre)) {
      const StereoFrame f = renderFrame(scene, cam, pose, config, 7);
      // The disparity a perfect matcher would report, in OpenCV's 1/16 px fixed point; only on the targets.
      std::vector<std::int16_t> disparity(f.left_depth.size(), -16);
      for (std::size_t i = 0; i < disparity.size(); ++i)
        if (f.target_mask[i]) disparity[i] = std::int16_t(std::lround(16.0 * cam.fx * cam.baseline / f.left_depth[i]));
      const auto points = reprojectDisparity(disparity, cam, pose, 20.0);
      REQUIRE(points.size() == std::size_t(std::count(f.target_mask.begin(), f.target_mask.end(), 1)));
      REQUIRE(points.size() > 100);
      std::vector<double> errors;
      for (const auto& p : points) errors.push_back(boxSurfaceDistance(scene.boxes, p));
      std::sort(errors.begin(), errors.end());
      CHECK(errors.back() < 0.1);                      // within one voxel
      CHECK(errors[errors.size() / 2] < 0.01);         // and mostly far better (1/16 px quantisation)
    }
  }
}

TEST_CASE("The ground truth of a single box has the expected voxels", "[stereo][truth]") {
  Scene scene = makeScene({Environment::Building, Texture::Plain, Layout::O});
  scene.boxes = {AxisBox{{0.02, 0.03, 0.0}, {0.52, 0.53, 0.5}}};
  scene.region = AxisBox{{-1.0, -1.0, 0.1}, {1.5, 1.5, 1.0}};
  const GroundTruth gt = sceneGroundTruth(scene, 0.1);
  // By hand: x [0.02, 0.52] overlaps voxels [0.0, 0.1) .. [0.5, 0.6): keys 0..5 from the origin, y alike; z
  // [0, 0.5] overlaps [0, 0.1) .. [0.4, 0.5), the ground layer [0, 0.1) is outside the region: z keys 1..4.
  octomap::KeySet expected;
  for (int i = 0; i <= 5; ++i)
    for (int j = 0; j <= 5; ++j)
      for (int k = 1; k <= 4; ++k) expected.insert(octomap::OcTreeKey(32768 + i, 32768 + j, 32768 + k));
  CHECK(gt.occupied.size() == 144);
  CHECK(std::all_of(expected.begin(), expected.end(), [&](const auto& k) { return gt.occupied.count(k) == 1; }));
  // Region: x centres -0.95 .. 1.45 (25), y alike, z 0.15 .. 0.95 (9).
  CHECK(gt.regionVoxelCount() == 25u * 25u * 9u);
}

TEST_CASE("The tetromino layouts give the expected ground truth", "[stereo][truth]") {
  // O: a 1.0 x 1.0 x 0.5 block from (-0.48, -0.47): 11 x 11 columns of 4 voxels above the ground layer.
  CHECK(sceneGroundTruth(makeScene({Environment::Parking, Texture::Plain, Layout::O}), 0.1).occupied.size() == 484);
  // I: 2.0 x 0.5: x from -0.98 to 1.02 (21 voxels), y from 0.03 to 0.53 (6): 21 * 6 * 4.
  CHECK(sceneGroundTruth(makeScene({Environment::Parking, Texture::Plain, Layout::I}), 0.1).occupied.size() == 504);
  for (Layout layout : {Layout::I, Layout::O, Layout::T, Layout::L, Layout::S}) {
    const auto cells = tetrominoCells(layout);
    REQUIRE(cells.size() == 4);
    // Connected: every cell shares an edge with another.
    for (const auto& a : cells)
      CHECK(std::count_if(cells.begin(), cells.end(), [&](const auto& b) {
              return std::abs(a[0] - b[0]) + std::abs(a[1] - b[1]) == 1;
            }) >= 1);
  }
}

TEST_CASE("Data set names parse and print back, bad ones are refused with the part named", "[stereo]") {
  const auto all = allDatasetNames();
  REQUIRE(all.size() == 20);
  for (const auto& n : all) CHECK(parseDatasetName(n.str()).str() == n.str());
  CHECK_THROWS_WITH(parseDatasetName("garden-plain-L"), Catch::Contains("environment"));
  CHECK_THROWS_WITH(parseDatasetName("building-striped-L"), Catch::Contains("texture"));
  CHECK_THROWS_WITH(parseDatasetName("building-plain-Z"), Catch::Contains("layout"));
  CHECK_THROWS_WITH(parseDatasetName("building"), Catch::Contains("ENV-TEXTURE-LAYOUT"));
}
