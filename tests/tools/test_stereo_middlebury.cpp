// The real Middlebury 2006 pair (Aloe, from Debian's opencv-doc) as a data set: its camera model, its
// ground truth, determinism, and the rendered sets' SGBM settings.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>
#include <tuple>

#include <catch2/catch.hpp>

#include "occsweep/eval/dataset.hpp"
#include "occsweep/stereo/cloud.hpp"
#include "occsweep/stereo/generate.hpp"
#include "occsweep/stereo/middlebury.hpp"
#include "occsweep/stereo/ranking.hpp"
#include "occsweep/sweeps/grid.hpp"
#include "test_helpers.hpp"

using namespace occsweep;
using namespace occsweep::stereo;
namespace fs = std::filesystem;

namespace {

// CI installs opencv-doc through tools/setup.sh; without it this fails and says what to install.
const MiddleburyPair& aloePair() {
  static const MiddleburyPair pair = [] {
    for (const char* name : {"aloeL.jpg", "aloeR.jpg", "aloeGT.png"})
      if (!fs::exists(kOpenCvSampleData / name))
        FAIL((kOpenCvSampleData / name).string() + " is missing: install Debian's opencv-doc package "
             "(apt-get install opencv-doc; tools/setup.sh does)");
    return readMiddleburyPair(kOpenCvSampleData / "aloeL.jpg", kOpenCvSampleData / "aloeR.jpg",
                              kOpenCvSampleData / "aloeGT.png");
  }();
  return pair;
}

// Rows [top, top + h) and columns [left, left + w) of both images and the truth: a fast stand-in for the pair.
MiddleburyPair crop(const MiddleburyPair& p, int left, int top, int w, int h) {
  MiddleburyPair c;
  c.left = {w, h, {}}, c.right = {w, h, {}};
  for (int v = top; v < top + h; ++v)
    for (int u = left; u < left + w; ++u) {
      const std::size_t i = std::size_t(v) * p.left.width + u;
      c.left.pixels.push_back(p.left.pixels[i]);
      c.right.pixels.push_back(p.right.pixels[i]);
      c.truth_disparity.push_back(p.truth_disparity[i]);
    }
  return c;
}

}  // namespace

TEST_CASE("Middlebury camera: a disparity of 100 px at (1000, 100) of a full-size image is the hand-computed point",
          "[stereo][middlebury]") {
  const MiddleburyCamera camera;  // f 3740 px, B 0.16 m, doffs 270 px (Aloe)
  const StereoCamera cam = middleburyStereoCamera(camera, 1282, 1110);
  CHECK(cam.cx == 640.5);
  CHECK(cam.cy == 554.5);
  std::vector<std::int16_t> disparity(std::size_t(1282) * 1110, -16);
  disparity[std::size_t(100) * 1282 + 1000] = 16 * 100;
  const auto points = reprojectDisparity(withDisparityOffset(disparity, camera.doffs_px), cam, CameraPose{}, 20.0);
  REQUIRE(points.size() == 1);
  // Z = 3740 * 0.16 / (100 + 270) = 1.6172973 m; X = (1000 - 640.5) Z / 3740; Y = (100 - 554.5) Z / 3740.
  CHECK(points[0].z() == Approx(1.6172973).epsilon(1e-7));
  CHECK(points[0].x() == Approx(0.1554595).epsilon(1e-6));
  CHECK(points[0].y() == Approx(-0.1965405).epsilon(1e-6));

  // The ground truth goes through the same model: a truth value of 100 at that pixel is the same point.
  MiddleburyPair pair;
  pair.left = {1282, 1110, std::vector<std::uint8_t>(std::size_t(1282) * 1110, 0)};
  pair.right = pair.left;
  pair.truth_disparity.assign(std::size_t(1282) * 1110, 0);
  pair.truth_disparity[std::size_t(100) * 1282 + 1000] = 100;
  const auto truth = truthPoints(pair, camera);
  REQUIRE(truth.size() == 1);
  CHECK((truth[0] - points[0]).norm() < 1e-12);
}

TEST_CASE("Middlebury truth voxels: the centre of each voxel holding a point, once", "[stereo][middlebury]") {
  const auto truth = voxelCentreTruth({{0.01, 0.02, 1.23}, {0.09, 0.08, 1.21}, {-0.01, 0.0, 1.29}}, 0.1);
  REQUIRE(truth.points.size() == 2);  // the first two share voxel (0, 0, 12)
  CHECK(truth.points[0].x() == Approx(-0.05));
  CHECK(truth.points[1].x() == Approx(0.05));
  CHECK(truth.points[1].y() == Approx(0.05));
  CHECK(truth.points[1].z() == Approx(1.25));
}

TEST_CASE("Aloe: full size, ground truth in full-size pixels, a scene 1.2 to 2 m away", "[stereo][middlebury]") {
  const MiddleburyPair& pair = aloePair();
  CHECK(pair.left.width == 1282);  // the sets' full size (half: 641, third: 427)
  CHECK(pair.left.height == 1110);
  int smallest = 256, largest = 0;  // of the known disparities (0 = unknown)
  for (const auto d : pair.truth_disparity)
    if (d > 0) smallest = std::min(smallest, int(d)), largest = std::max(largest, int(d));
  CHECK(numDisparitiesCovering(pair) > largest);
  CHECK(numDisparitiesCovering(pair) - largest <= 16);
  const auto points = truthPoints(pair, MiddleburyCamera{});
  double zmin = 1e9, zmax = 0, xmin = 1e9, xmax = -1e9;
  for (const auto& p : points) zmin = std::min(zmin, p.z()), zmax = std::max(zmax, p.z()),
                               xmin = std::min(xmin, p.x()), xmax = std::max(xmax, p.x());
  CHECK(zmin == Approx(3740 * 0.16 / (largest + 270.0)));
  CHECK(zmax == Approx(3740 * 0.16 / (smallest + 270.0)));
  CHECK(zmin > 1.0);  // a table-top scene 1-2 m from the cameras
  CHECK(zmax < 2.0);
  CHECK(xmax - xmin < 0.7);  // 1282 px at f = 3740 px: 0.34 m per metre of depth
}

TEST_CASE("Aloe: SGBM with the grid's settings agrees with the ground truth read 1 unit = 1 px",
          "[stereo][middlebury]") {
  // A band of the pair keeps this fast; a wrong scale (half or third size), swapped images or a wrong decode
  // would put most disparities far from the truth.
  const MiddleburyPair band = crop(aloePair(), 300, 400, 700, 120);
  MiddleburySetSummary s;
  const SgbmParams params = parseSgbmParams("blockSize=5,uniquenessRatio=10,speckleWindowSize=100,speckleRange=2");
  (void)middleburyDataset(band, MiddleburyCamera{}, params, numDisparitiesCovering(aloePair()), 0.1, &s);
  CHECK(s.truth_pixels > 50000);
  CHECK(s.valid_fraction > 0.5);
  CHECK(s.bad1_fraction < 0.2);
}

TEST_CASE("Middlebury data set: equal inputs give equal bytes, other settings others", "[stereo][middlebury]") {
  const MiddleburyPair band = crop(aloePair(), 300, 400, 500, 100);
  const PointCloudGrid grid = loadPointCloudGrid(resolveGridPath("pointcloud"));
  const fs::path dir = test::processScratch("middlebury-determinism");
  auto hashOf = [&](std::uint64_t id, const std::string& folder) {
    writeDataset(middleburyDataset(band, MiddleburyCamera{}, grid.at(id), 224, 0.05), dir / folder);
    return datasetContentHash(dir / folder);
  };
  const std::string first = hashOf(800, "a"), again = hashOf(800, "b"), other = hashOf(1599, "c");
  CHECK(first == again);
  CHECK(first != other);
}

TEST_CASE("Middlebury sets use the rendered ci sets' ids and SGBM settings, only numDisparities differs",
          "[stereo][middlebury]") {
  const PointCloudGrid grid = loadPointCloudGrid(resolveGridPath("pointcloud"));
  const auto ids = middleburyPointCloudIds(grid);
  CHECK(ids == evenSubset(grid.size(), scaleConfig("ci").subset));
  const MiddleburyPair band = crop(aloePair(), 300, 400, 400, 60);
  GenerateConfig rendered;  // the ci scale
  for (const auto id : ids) {
    const Dataset d = middleburyDataset(band, MiddleburyCamera{}, grid.at(id), 224, 0.1);
    nlohmann::json expected = sourceJson(parseDatasetName("building-plain-O"), rendered,
                                         zedLikeCamera(320, 180), grid, std::int64_t(id), grid.at(id))["sgbm"];
    CHECK(expected["numDisparities"] == rendered.scale.num_disparities);
    expected["numDisparities"] = 224;
    CHECK(d.source["sgbm"] == expected);
  }
}

TEST_CASE("dataset middlebury: a missing input is an error naming the file, exit 2", "[stereo][middlebury][cli]") {
  const fs::path dir = test::processScratch("middlebury-cli");
  const auto r = test::runCli("dataset middlebury --left " + (dir / "none.jpg").string() + " --out " +
                              (dir / "out").string());
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("none.jpg") != std::string::npos);
  CHECK(!fs::exists(dir / "out"));
}

TEST_CASE("Middlebury --no-voxel-filter: every reprojected point, the same truth, the filter recorded in source",
          "[stereo][middlebury]") {
  const MiddleburyPair band = crop(aloePair(), 300, 400, 400, 60);
  const PointCloudGrid grid = loadPointCloudGrid(resolveGridPath("pointcloud"));
  const Dataset filtered = middleburyDataset(band, MiddleburyCamera{}, grid.at(800), 224, MiddleburyVoxels{0.05, true});
  const Dataset raw = middleburyDataset(band, MiddleburyCamera{}, grid.at(800), 224, MiddleburyVoxels{0.05, false});
  // The filter of the raw points is the filtered set: one code path, only the filter differs.
  REQUIRE(raw.scans.size() == 1);
  CHECK(raw.scans[0].points.size() > 2 * filtered.scans[0].points.size());
  CHECK(voxelFilter(raw.scans[0].points, 0.05) == filtered.scans[0].points);
  CHECK(raw.truth.points == filtered.truth.points);
  CHECK(raw.source.at("voxel_filter") == false);
  CHECK_FALSE(raw.source.contains("voxel_filter_leaf"));
  CHECK(filtered.source.at("voxel_filter_leaf") == 0.05);
  CHECK(raw.source.at("truth_leaf") == 0.05);
  CHECK(filtered.source.at("truth_leaf") == 0.05);
}

TEST_CASE("dataset middlebury --no-voxel-filter writes the raw points, and a bad --leaf exits 2 naming it",
          "[stereo][middlebury][cli]") {
  const fs::path dir = test::processScratch("middlebury-no-filter-cli");
  const auto r = test::runCli("dataset middlebury --no-voxel-filter --leaf 0.1 --out " + (dir / "raw").string());
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const Dataset d = readDataset(dir / "raw" / "pcs-0800");
  CHECK(d.source.at("voxel_filter") == false);
  CHECK(d.scans[0].points.size() > 500000);  // one per valid disparity of the full-size pair
  const auto bad = test::runCli("dataset middlebury --no-voxel-filter --leaf 0 --out " + (dir / "bad").string());
  CHECK(bad.exit_code == 2);
  CHECK(bad.output.find("--leaf") != std::string::npos);
}

TEST_CASE("dataset middlebury refuses a leaf below a micrometre before the pair is read, naming the flag and bound",
          "[stereo][middlebury][cli]") {
  // Old binary: "voxelFilter: point 0 is not finite or too far out" for either flag at 1e-300, once the pair was
  // read and matched.
  const fs::path dir = test::processScratch("middlebury-tiny-leaf");
  for (const std::string flag : {"--voxel-filter", "--leaf"}) {
    const auto r = test::runCli("dataset middlebury " + flag + " 1e-300 --left " + (dir / "missing.png").string() +
                                " --out " + (dir / "out").string());
    INFO(r.output);
    CHECK(r.exit_code == 2);
    CHECK(r.output.find(flag + " must be a number >= 1e-06, got 1e-300") != std::string::npos);
    CHECK_FALSE(fs::exists(dir / "out"));
  }
}

TEST_CASE("dataset middlebury --voxel-filter filters at its own leaf while truth stays at --leaf", "[stereo][middlebury][cli]") {
  const fs::path dir = test::processScratch("middlebury-filter-leaf-cli");
  REQUIRE(test::runCli("dataset middlebury --leaf 0.1 --out " + (dir / "at-leaf").string()).exit_code == 0);
  const auto r = test::runCli("dataset middlebury --leaf 0.1 --voxel-filter 0.05 --out " + (dir / "half").string());
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const Dataset at_leaf = readDataset(dir / "at-leaf" / "pcs-0800"), half = readDataset(dir / "half" / "pcs-0800");
  CHECK(half.source.at("voxel_filter_leaf") == 0.05);
  CHECK(half.source.at("truth_leaf") == 0.1);
  CHECK(at_leaf.source.at("voxel_filter_leaf") == 0.1);
  CHECK(half.truth.points.size() == at_leaf.truth.points.size());  // the truth does not follow the filter
  // One point per 0.05 m voxel (each at its points' centroid, so inside it), and more of them than at 0.1 m.
  std::set<std::tuple<long, long, long>> voxels;
  for (const auto& p : half.scans[0].points)
    voxels.insert({std::lround(std::floor(p.x() / 0.05)), std::lround(std::floor(p.y() / 0.05)),
                   std::lround(std::floor(p.z() / 0.05))});
  CHECK(voxels.size() > half.scans[0].points.size() * 99 / 100);  // float rounding may move a centroid across a face
  CHECK(half.scans[0].points.size() > 2 * at_leaf.scans[0].points.size());
  const auto both = test::runCli("dataset middlebury --voxel-filter 0.05 --no-voxel-filter --out " + (dir / "both").string());
  CHECK(both.exit_code == 2);
  CHECK(both.output.find("--voxel-filter") != std::string::npos);
  CHECK_FALSE(fs::exists(dir / "both"));
}
