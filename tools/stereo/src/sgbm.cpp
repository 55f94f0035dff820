#include "occsweep/stereo/sgbm.hpp"

#include <sstream>
#include <stdexcept>

#include <opencv2/calib3d.hpp>

namespace occsweep::stereo {

nlohmann::json SgbmParams::toJson() const {
  return {{"blockSize", block_size},          {"uniquenessRatio", uniqueness_ratio},
          {"speckleWindowSize", speckle_window_size}, {"speckleRange", speckle_range},
          {"disp12MaxDiff", disp12_max_diff}, {"P1", p1()}, {"P2", p2()}};
}

nlohmann::json sgbmSettingsJson(const SgbmParams& params, int num_disparities) {
  nlohmann::json j = params.toJson();
  j["mode"] = "MODE_SGBM";
  j["minDisparity"] = 0;
  j["numDisparities"] = num_disparities;
  j["channels"] = 1;
  return j;
}

void validate(const SgbmParams& p) {
  if (p.block_size < 1 || p.block_size > 51 || p.block_size % 2 == 0)
    throw std::invalid_argument("blockSize " + std::to_string(p.block_size) + ": must be odd, 1 to 51");
  if (p.uniqueness_ratio < 0 || p.uniqueness_ratio > 100)
    throw std::invalid_argument("uniquenessRatio " + std::to_string(p.uniqueness_ratio) + ": must be 0 to 100");
  if (p.speckle_window_size < 0) throw std::invalid_argument("speckleWindowSize: must be >= 0");
  if (p.speckle_range < 0) throw std::invalid_argument("speckleRange: must be >= 0");
  if (p.disp12_max_diff < -1) throw std::invalid_argument("disp12MaxDiff: must be >= -1 (-1 switches the check off)");
}

SgbmParams parseSgbmParams(const std::string& text) {
  SgbmParams p;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    const auto eq = item.find('=');
    if (eq == std::string::npos) throw std::invalid_argument("--sgbm '" + item + "': expected key=value");
    const std::string key = item.substr(0, eq), value = item.substr(eq + 1);
    int v = 0;
    std::size_t used = 0;
    try {
      v = std::stoi(value, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != value.size()) throw std::invalid_argument("--sgbm " + key + ": '" + value + "' is not an integer");
    if (key == "blockSize") p.block_size = v;
    else if (key == "uniquenessRatio") p.uniqueness_ratio = v;
    else if (key == "speckleWindowSize") p.speckle_window_size = v;
    else if (key == "speckleRange") p.speckle_range = v;
    else if (key == "disp12MaxDiff") p.disp12_max_diff = v;
    else throw std::invalid_argument("--sgbm: unknown key '" + key +
                                     "' (blockSize, uniquenessRatio, speckleWindowSize, speckleRange, disp12MaxDiff)");
  }
  validate(p);
  return p;
}

SgbmParams matcherParams(const SgbmParams& params) {
  SgbmParams matcher = params;
  matcher.speckle_window_size = 0;
  matcher.speckle_range = 0;
  return matcher;
}

std::vector<std::int16_t> computeDisparity(const StereoFrame& frame, const SgbmParams& p, int num_disparities) {
  if (num_disparities <= 0 || num_disparities % 16 != 0)
    throw std::invalid_argument("numDisparities must be a positive multiple of 16");
  const int w = frame.left.width, h = frame.left.height;
  const cv::Mat left(h, w, CV_8UC1, const_cast<std::uint8_t*>(frame.left.pixels.data()));
  const cv::Mat right(h, w, CV_8UC1, const_cast<std::uint8_t*>(frame.right.pixels.data()));
  auto sgbm = cv::StereoSGBM::create(0, num_disparities, p.block_size, p.p1(), p.p2(), p.disp12_max_diff, 0,
                                     p.uniqueness_ratio, p.speckle_window_size, p.speckle_range,
                                     cv::StereoSGBM::MODE_SGBM);
  cv::Mat disparity;
  sgbm->compute(left, right, disparity);
  CV_Assert(disparity.type() == CV_16S && disparity.isContinuous());
  const auto* d = disparity.ptr<std::int16_t>();
  return std::vector<std::int16_t>(d, d + std::size_t(w) * h);
}

std::vector<std::int16_t> computeMatcherDisparity(const StereoFrame& frame, const SgbmParams& params,
                                                  int num_disparities) {
  return computeDisparity(frame, matcherParams(params), num_disparities);
}

void filterSpecklesAsCompute(std::vector<std::int16_t>& disparity, int width, int height, const SgbmParams& params) {
  if (params.speckle_window_size <= 0) return;
  if (disparity.size() != std::size_t(width) * height)
    throw std::invalid_argument("filterSpecklesAsCompute: the disparity is not width x height");
  cv::Mat disp(height, width, CV_16SC1, disparity.data());
  // compute passes its own buffer (the matcher's, reused), which also keeps OpenCV off its IPP branch (taken only
  // without one); filterSpeckles clears its labels and writes the rest before reading, so any buffer gives the
  // same result. One per thread, kept: no allocation per call.
  thread_local cv::Mat buffer;
  constexpr int kMinDisparity = 0;  // computeDisparity's
  cv::filterSpeckles(disp, (kMinDisparity - 1) * cv::StereoMatcher::DISP_SCALE, params.speckle_window_size,
                     cv::StereoMatcher::DISP_SCALE * params.speckle_range, buffer);
}

std::string openCvVersion() { return CV_VERSION; }

}  // namespace occsweep::stereo
