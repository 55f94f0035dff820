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

}  // namespace occsweep::stereo
