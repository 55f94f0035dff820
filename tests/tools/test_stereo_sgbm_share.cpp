// Generation computes SGBM's matcher once per matcher combination and derives every speckle variant
// with compute's own speckle filter (docs/datasets.md, "How generation shares work"); the point cloud sets are
// the bytes each set computed alone gives.
#include <algorithm>
#include <random>
#include <set>

#include <catch2/catch.hpp>

#include "occsweep/stereo/cloud.hpp"
#include "occsweep/stereo/generate.hpp"
#include "occsweep/sweeps/grid.hpp"
#include "test_helpers.hpp"

using namespace occsweep;
using namespace occsweep::stereo;
namespace fs = std::filesystem;

namespace {

// A rendered left/right pair of data set `name` seen from keyframe `keyframe` of an 8-keyframe orbit.
StereoFrame renderedFrame(const StereoCamera& cam, const std::string& name, int keyframe, std::uint64_t seed) {
  const Scene scene = makeScene(parseDatasetName(name), SceneConfig{});
  OrbitConfig orbit;
  orbit.keyframes = 8;
  return renderFrame(scene, cam, orbitPoses(orbit, scene.centre)[std::size_t(keyframe)], RenderConfig{}, seed);
}

int oddIn(std::mt19937_64& rng, int lo, int hi) {
  return lo + 2 * std::uniform_int_distribution<int>(0, (hi - lo) / 2)(rng);
}

SgbmParams randomParams(std::mt19937_64& rng) {
  auto in = [&](int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); };
  SgbmParams p;
  p.block_size = oddIn(rng, 1, 15);
  p.uniqueness_ratio = in(0, 30);
  p.speckle_window_size = in(0, 4) == 0 ? 0 : in(1, 400);
  p.speckle_range = in(0, 16);
  p.disp12_max_diff = in(-1, 4);
  return p;
}

int countInvalid(const std::vector<std::int16_t>& disparity) {
  return int(std::count(disparity.begin(), disparity.end(), std::int16_t(-16)));
}

GenerateConfig fewKeyframesOfCi(int keyframes) {
  GenerateConfig c;
  c.scale = scaleConfig("ci");
  c.scale.keyframes = keyframes;
  c.preview = false;
  c.progress = false;
  return c;
}

}  // namespace

TEST_CASE("A speckle variant derived from the matcher's disparity equals StereoSGBM::compute with every parameter",
          "[stereo][sgbm]") {
  const StereoCamera cam = zedLikeCamera(160, 90);
  const char* names[] = {"building-voronoi-I", "parking-plain-S", "building-plain-T", "parking-voronoi-L"};
  int filtered_some = 0;  // variants where the speckle filter invalidated pixels: the property was exercised
  for (std::uint64_t seed = 1; seed <= 40; ++seed) {
    std::mt19937_64 rng(seed);
    const StereoFrame frame = renderedFrame(cam, names[seed % 4], int(seed % 8), seed);
    const SgbmParams params = randomParams(rng);
    const int num_disparities = 16 * std::uniform_int_distribution<int>(1, 3)(rng);
    INFO("seed " << seed << ": " << params.toJson().dump() << ", numDisparities " << num_disparities);
    const auto whole = computeDisparity(frame, params, num_disparities);
    const auto matcher = computeMatcherDisparity(frame, params, num_disparities);
    auto derived = matcher;
    filterSpecklesAsCompute(derived, cam.width, cam.height, params);
    REQUIRE(derived == whole);
    filtered_some += countInvalid(derived) > countInvalid(matcher);
  }
  CHECK(filtered_some >= 10);
}

TEST_CASE("The speckle filter only invalidates pixels, and does nothing at speckleWindowSize 0", "[stereo][sgbm]") {
  const StereoCamera cam = zedLikeCamera(160, 90);
  const StereoFrame frame = renderedFrame(cam, "parking-voronoi-O", 3, 5);
  SgbmParams params;
  params.speckle_window_size = 0;
  const auto matcher = computeMatcherDisparity(frame, params, 32);
  auto unchanged = matcher;
  filterSpecklesAsCompute(unchanged, cam.width, cam.height, params);
  CHECK(unchanged == matcher);
  params.speckle_window_size = 400, params.speckle_range = 1;
  auto filtered = matcher;
  filterSpecklesAsCompute(filtered, cam.width, cam.height, params);
  int invalidated = 0;
  for (std::size_t p = 0; p < matcher.size(); ++p) {
    if (filtered[p] == matcher[p]) continue;
    CHECK(filtered[p] == -16);
    invalidated += 1;
  }
  CHECK(invalidated > 0);
}

// Every one of the 1,600 parameter sets at ci scale (320 x 180, 32 disparities) on 2 keyframes: all 24 would take
// each set's own SGBM 12 times as long, far past the minute a test may take on 2 cores, and each keyframe is
// computed independently of the others (the orbit's poses for 2 keyframes differ from 24's, the code path does
// not; bench_dataset compares whole sets of 24 keyframes on an even subset).
TEST_CASE("All 1,600 point cloud sets: sharing the matcher writes the bytes each set computed alone writes",
          "[stereo][sgbm][generate]") {
  const PointCloudGrid grid = loadPointCloudGrid(resolveGridPath("pointcloud"));
  GenerateConfig config = fewKeyframesOfCi(2);
  for (std::uint64_t id = 0; id < grid.size(); ++id) config.pcs_ids.push_back(id);
  const fs::path alone = test::processScratch("sgbm-share-alone"),
                 shared = test::processScratch("sgbm-share-shared");
  const DatasetName name = parseDatasetName("building-voronoi-L");
  config.share_matcher = false;
  const DatasetSummary before = generateDataset(name, config, grid, alone);
  config.share_matcher = true;
  const DatasetSummary after = generateDataset(name, config, grid, shared);

  const auto files = test::filesUnder(alone);  // all but timing.json, whose seconds are the only variable bytes
  REQUIRE(files == test::filesUnder(shared));
  CHECK(files.size() >= grid.size() * (2 + 1));  // per set, a scan per keyframe and its metadata at least
  for (const auto& f : files) {
    INFO(f);
    REQUIRE(test::bytesOf(alone / f) == test::bytesOf(shared / f));
  }
  // The comparison is not between equal sets only: the speckle settings change the clouds of one matcher.
  REQUIRE(before.sets.size() == grid.size());
  REQUIRE(after.sets.size() == grid.size());
  std::set<std::uint64_t> point_counts;
  for (const auto& set : after.sets)
    if (matcherParams(set.params) == matcherParams(grid.at(0))) point_counts.insert(set.points);
  CHECK(point_counts.size() > 1);
  // 3,200 sets, about 1 GB: kept only when a REQUIRE above stopped the test, for a look at the differing file
  fs::remove_all(alone);
  fs::remove_all(shared);
}

TEST_CASE("Without the voxel filter, sharing the matcher writes the bytes each set computed alone writes",
          "[stereo][sgbm][generate]") {
  const PointCloudGrid grid = loadPointCloudGrid(resolveGridPath("pointcloud"));
  GenerateConfig config = fewKeyframesOfCi(2);
  config.voxel_filter = false;
  config.preview = true;  // the previews too: keyframe 0's disparity of every set
  for (std::uint64_t id = 0; id < 64; ++id) config.pcs_ids.push_back(id);  // blockSize 3, uniquenessRatio 5: 4 groups
  const fs::path alone = test::processScratch("sgbm-share-raw-alone"),
                 shared = test::processScratch("sgbm-share-raw-shared");
  const DatasetName name = parseDatasetName("parking-plain-T");
  config.share_matcher = false;
  (void)generateDataset(name, config, grid, alone);
  config.share_matcher = true;
  (void)generateDataset(name, config, grid, shared);
  const auto files = test::filesUnder(alone);
  REQUIRE(files == test::filesUnder(shared));
  CHECK(files.size() >= 64 * (2 + 1) + 64);  // scans, manifests, previews
  for (const auto& f : files) {
    INFO(f);
    REQUIRE(test::bytesOf(alone / f) == test::bytesOf(shared / f));
  }
  fs::remove_all(alone);  // kept only when a REQUIRE above stopped the test
  fs::remove_all(shared);
}

TEST_CASE("The shared voxel filter gives voxelFilter's floats for any pixels invalidated, at any voxel span",
          "[stereo][sgbm][cloud]") {
  const StereoCamera cam = zedLikeCamera(160, 90);
  const StereoFrame frame = renderedFrame(cam, "building-voronoi-S", 2, 11);
  const auto matcher = computeMatcherDisparity(frame, SgbmParams{}, 32);
  OrbitConfig orbit;
  orbit.keyframes = 8;
  const CameraPose pose = orbitPoses(orbit, Eigen::Vector3d(1, 2, 0))[5];
  // 0.1 m: a span that packs into a radix key; 1e-7 m: one too wide, sorted by comparison
  for (const double leaf : {0.1, 1e-7}) {
    const SharedVoxelFilter shared(matcher, cam, pose, 20.0, leaf);
    for (std::uint64_t seed = 1; seed <= 6; ++seed) {
      std::mt19937_64 rng(seed);
      const double drop = 0.2 * double(seed - 1);  // 0 to all but none
      auto variant = matcher;
      for (auto& d : variant)
        if (std::bernoulli_distribution(drop)(rng)) d = -16;
      const auto expected = voxelFilter(reprojectDisparity(variant, cam, pose, 20.0), leaf);
      const auto got = shared.filtered(variant);
      INFO("leaf " << leaf << ", seed " << seed);
      REQUIRE(got.size() == expected.size());
      CHECK(std::equal(got.begin(), got.end(), expected.begin(), [](const auto& a, const auto& b) {
        return a.x() == b.x() && a.y() == b.y() && a.z() == b.z();
      }));
    }
  }
}
