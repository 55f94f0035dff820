#include "occsweep/stereo/middlebury.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <set>
#include <stdexcept>
#include <string>

#include <png.h>

#include "jpeg_grey.hpp"
#include "occsweep/io/data_error.hpp"
#include "occsweep/io/bounded_read.hpp"
#include "occsweep/data/import_depth.hpp"
#include "occsweep/data/import_truth.hpp"
#include "occsweep/eval/naive.hpp"
#include "occsweep/stereo/cloud.hpp"
#include "occsweep/stereo/generate.hpp"

namespace occsweep::stereo {
namespace {

// The rendered sets' maximum depth (a ZED's range): one home, GenerateConfig.
const double kMaxDepth = GenerateConfig{}.max_depth;

/// A JPEG, or an 8-bit grey PNG (the sets' own view1.png, view5.png once converted to grey).
GreyImage readGreyImage(const std::filesystem::path& file) {
  const std::string bytes = readFileBytes(file);
  if (bytes.size() >= 8 && png_sig_cmp(reinterpret_cast<png_const_bytep>(bytes.data()), 0, 8) == 0) {
    const DepthImage png = decodePng(bytes, file);
    GreyImage grey{png.width, png.height, std::vector<std::uint8_t>(png.values.size())};
    for (std::size_t i = 0; i < png.values.size(); ++i) {
      if (png.values[i] > 255) throw DataError(file, "header", "16-bit PNG: a stereo image must be 8-bit");
      grey.pixels[i] = std::uint8_t(png.values[i]);
    }
    return grey;
  }
  return decodeJpegGrey(bytes, file);
}

void requireSize(const std::filesystem::path& file, int w, int h, const GreyImage& left) {
  if (w != left.width || h != left.height)
    throw DataError(file, "size", std::to_string(w) + "x" + std::to_string(h) + ", but the left image is " +
                                      std::to_string(left.width) + "x" + std::to_string(left.height));
}

}  // namespace

MiddleburyPair readMiddleburyPair(const std::filesystem::path& left, const std::filesystem::path& right,
                                  const std::filesystem::path& truth) {
  MiddleburyPair pair;
  pair.left = readGreyImage(left);
  pair.right = readGreyImage(right);
  requireSize(right, pair.right.width, pair.right.height, pair.left);
  const DepthImage gt = readDepthImage(truth);
  requireSize(truth, gt.width, gt.height, pair.left);
  pair.truth_disparity.resize(gt.values.size());
  for (std::size_t i = 0; i < gt.values.size(); ++i) {
    if (gt.values[i] > 255)
      throw DataError(truth, "header", "16-bit PNG: Middlebury 2006 disparities are 8-bit (full-size pixels)");
    pair.truth_disparity[i] = std::uint8_t(gt.values[i]);
  }
  return pair;
}

StereoCamera middleburyStereoCamera(const MiddleburyCamera& c, int width, int height) {
  return StereoCamera{width, height, c.focal_px, 0.5 * (width - 1), 0.5 * (height - 1), c.baseline_m};
}

std::vector<std::int16_t> withDisparityOffset(const std::vector<std::int16_t>& disparity, double doffs_px) {
  const int offset = int(std::lround(16.0 * doffs_px));
  std::vector<std::int16_t> out(disparity);
  for (auto& d : out) {
    if (d <= 0) continue;
    if (int(d) + offset > 32767)
      throw std::invalid_argument("disparity offset " + std::to_string(doffs_px) + " px: disparity + offset must stay "
                                  "below 2048 px (OpenCV's fixed point, 1/16 px in 16 bits)");
    d = std::int16_t(int(d) + offset);
  }
  return out;
}

std::vector<Eigen::Vector3d> truthPoints(const MiddleburyPair& pair, const MiddleburyCamera& camera) {
  std::vector<std::int16_t> fixed(pair.truth_disparity.size());
  for (std::size_t i = 0; i < fixed.size(); ++i) fixed[i] = std::int16_t(16 * int(pair.truth_disparity[i]));
  return reprojectDisparity(withDisparityOffset(fixed, camera.doffs_px),
                            middleburyStereoCamera(camera, pair.left.width, pair.left.height), CameraPose{}, kMaxDepth);
}

TruthSources voxelCentreTruth(const std::vector<Eigen::Vector3d>& points, double leaf) {
  std::set<VoxelFilterKey> keys;  // (z, y, x), voxelFilter's voxels and order
  for (const auto& p : points) keys.insert(voxelFilterKey(p, leaf));
  TruthSources truth;
  for (const auto& k : keys)
    truth.points.emplace_back(float((double(k[2]) + 0.5) * leaf), float((double(k[1]) + 0.5) * leaf),
                              float((double(k[0]) + 0.5) * leaf));
  return truth;
}

int numDisparitiesCovering(const MiddleburyPair& pair) {
  const int largest = pair.truth_disparity.empty()
                          ? 0 : int(*std::max_element(pair.truth_disparity.begin(), pair.truth_disparity.end()));
  return 16 * (largest / 16 + 1);
}

std::vector<std::uint64_t> middleburyPointCloudIds(const PointCloudGrid& grid) {
  return evenSubset(grid.size(), scaleConfig("ci").subset);
}

namespace {

// What to repeat the set: camera and the SGBM block as generate's sourceJson records them.
// The filter as the generator records it (ranking.cpp, realism.cpp): voxel_filter_leaf when filtered,
// voxel_filter false when not; the truth's voxels always as truth_leaf.
nlohmann::json sourceOf(const StereoCamera& cam, const MiddleburyCamera& camera, const SgbmParams& params,
                        int num_disparities, const MiddleburyVoxels& voxels) {
  nlohmann::json j = {
      {"generator", "occsweep dataset middlebury"},
      {"camera", {{"width", cam.width}, {"height", cam.height}, {"fx", cam.fx}, {"cx", cam.cx}, {"cy", cam.cy},
                  {"baseline", cam.baseline}, {"doffs", camera.doffs_px}}},
      {"scan", "one: the left camera at the origin, camera axes (x right, y down, z forward)"},
      {"truth", "voxel centres of the ground-truth disparity's points at truth_leaf"}, {"truth_leaf", voxels.leaf},
      {"max_depth", kMaxDepth}, {"sgbm", sgbmSettingsJson(params, num_disparities)}};
  if (voxels.voxel_filter) j["voxel_filter_leaf"] = voxels.filterLeaf();
  else j["voxel_filter"] = false;
  return j;
}

MiddleburySetSummary summarise(const MiddleburyPair& pair, const std::vector<std::int16_t>& disparity,
                               const Dataset& d, double leaf) {
  MiddleburySetSummary s;
  std::uint64_t valid = 0, bad = 0;
  for (std::size_t i = 0; i < disparity.size(); ++i) {
    if (pair.truth_disparity[i] == 0) continue;
    s.truth_pixels += 1;
    if (disparity[i] <= 0) continue;
    valid += 1;
    bad += std::abs(disparity[i] / 16.0 - pair.truth_disparity[i]) > 1.0;
  }
  s.points = pointCount(d.scans);
  s.valid_fraction = s.truth_pixels ? double(valid) / double(s.truth_pixels) : 0.0;
  s.bad1_fraction = valid ? double(bad) / double(valid) : 0.0;
  s.naive = naiveConfusion(d.scans, makeGroundTruth(d.truth, d.region, leaf));
  return s;
}

}  // namespace

Dataset middleburyDataset(const MiddleburyPair& pair, const MiddleburyCamera& camera, const SgbmParams& params,
                          int num_disparities, const MiddleburyVoxels& voxels, MiddleburySetSummary* summary) {
  const StereoCamera cam = middleburyStereoCamera(camera, pair.left.width, pair.left.height);
  StereoFrame frame;
  frame.left = pair.left;
  frame.right = pair.right;
  const std::vector<std::int16_t> disparity = computeDisparity(frame, params, num_disparities);
  Scan scan;  // the left camera at the origin, camera axes (x right, y down, z forward)
  scan.origin = octomap::point3d(0, 0, 0);
  scan.view = leftCameraView(cam, CameraPose{});
  const std::vector<Eigen::Vector3d> points =
      reprojectDisparity(withDisparityOffset(disparity, camera.doffs_px), cam, CameraPose{}, kMaxDepth);
  scan.points = voxels.voxel_filter ? voxelFilter(points, voxels.filterLeaf()) : toPoint3d(points);
  if (scan.points.empty()) throw std::runtime_error("SGBM found no valid disparity in the pair");
  Dataset d;
  d.scans.push_back(std::move(scan));
  d.truth = voxelCentreTruth(truthPoints(pair, camera), voxels.leaf);
  if (d.truth.points.empty()) throw std::runtime_error("the ground truth has no known disparity");
  d.region = truthRegion(d.truth);
  d.source = sourceOf(cam, camera, params, num_disparities, voxels);
  if (summary) *summary = summarise(pair, disparity, d, voxels.leaf);
  return d;
}

}  // namespace occsweep::stereo
