// OpenCV's StereoSGBM on a rendered pair, and the point cloud parameters (docs/definitions.md, Point cloud parameters).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "render.hpp"

namespace occsweep::stereo {

/// One point cloud parameter combination. P1 = 8 c b^2, P2 = 32 c b^2 with c = 1 channel (grey images).
struct SgbmParams {
  int block_size = 5;
  int uniqueness_ratio = 10;
  int speckle_window_size = 100;
  int speckle_range = 2;
  int disp12_max_diff = 1;

  [[nodiscard]] int p1() const { return 8 * block_size * block_size; }
  [[nodiscard]] int p2() const { return 32 * block_size * block_size; }
  [[nodiscard]] nlohmann::json toJson() const;
  friend bool operator==(const SgbmParams&, const SgbmParams&) = default;
};

/// "blockSize=5,uniquenessRatio=10,speckleWindowSize=100,speckleRange=2,disp12MaxDiff=1"; unnamed keys keep
/// their defaults. Throws std::invalid_argument naming the key and the rule (odd blockSize 1-51, ranges >= 0...).
[[nodiscard]] SgbmParams parseSgbmParams(const std::string& text);
void validate(const SgbmParams& params);

/// What computeDisparity runs, as data sets record it (manifest `source.sgbm`): the parameters and its fixed
/// settings (MODE_SGBM, minDisparity 0, one channel, `num_disparities`).
[[nodiscard]] nlohmann::json sgbmSettingsJson(const SgbmParams& params, int num_disparities);

/// Disparity of the left image in OpenCV's fixed point (1/16 px); <= 0 is invalid. MODE_SGBM, minDisparity 0,
/// preFilterCap OpenCV's default. `num_disparities` a positive multiple of 16.
[[nodiscard]] std::vector<std::int16_t> computeDisparity(const StereoFrame& frame, const SgbmParams& params,
                                                         int num_disparities);

/// StereoSGBM::compute runs the matcher (where blockSize, uniquenessRatio, disp12MaxDiff, P1 and P2 act, the
/// left-right check included), a 3x3 median, and only then, when speckleWindowSize > 0,
/// filterSpeckles(disp, (minDisparity - 1) * 16, speckleWindowSize, 16 * speckleRange, buffer). So every speckle
/// variant of one matcher combination shares the first two steps (docs/datasets.md, "How generation shares work"):
///   computeDisparity(frame, p, n) == filterSpecklesAsCompute(computeMatcherDisparity(frame, p, n), w, h, p).

/// `params` with speckleWindowSize = speckleRange = 0: what the matcher and the median see (the key that groups
/// speckle variants).
[[nodiscard]] SgbmParams matcherParams(const SgbmParams& params);

/// computeDisparity with speckleWindowSize 0: the matcher and the median, no speckle filter.
[[nodiscard]] std::vector<std::int16_t> computeMatcherDisparity(const StereoFrame& frame, const SgbmParams& params,
                                                                int num_disparities);

/// compute's last step on a matcher disparity, in place: nothing when speckleWindowSize is 0, else OpenCV's
/// filterSpeckles with compute's arguments (new value -16, i.e. (minDisparity - 1) * 16; maxDiff 16 speckleRange).
/// Only ever sets pixels to -16; every other pixel keeps its value.
void filterSpecklesAsCompute(std::vector<std::int16_t>& disparity, int width, int height, const SgbmParams& params);

/// The OpenCV version this library was built with (CV_VERSION), for benchmarks' records.
[[nodiscard]] std::string openCvVersion();

}  // namespace occsweep::stereo
