// PNG previews for docs/datasets.md, written with OpenCV's imgcodecs.
#include <filesystem>
#include <stdexcept>
#include <unistd.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "occsweep/stereo/generate.hpp"

namespace occsweep::stereo {
namespace {

void writeAtomically(const cv::Mat& image, const std::filesystem::path& file) {
  const std::filesystem::path tmp = file.string() + ".tmp-" + std::to_string(::getpid()) + ".png";
  if (!cv::imwrite(tmp.string(), image)) throw std::runtime_error(file.string() + ": cannot write the PNG");
  std::filesystem::rename(tmp, file);
}

}  // namespace

void writeGreyPng(const GreyImage& image, const std::filesystem::path& file) {
  const cv::Mat m(image.height, image.width, CV_8UC1, const_cast<std::uint8_t*>(image.pixels.data()));
  writeAtomically(m, file);
}

void writeDisparityPng(const std::vector<std::int16_t>& disparity, int width, int height, int num_disparities,
                       const std::filesystem::path& file) {
  cv::Mat scaled(height, width, CV_8UC1), colour;
  for (int v = 0; v < height; ++v)
    for (int u = 0; u < width; ++u) {
      const int raw = disparity[std::size_t(v) * width + u];
      scaled.at<std::uint8_t>(v, u) = raw <= 0 ? 0 : std::uint8_t(std::min(255, 1 + raw * 254 / (16 * num_disparities)));
    }
  cv::applyColorMap(scaled, colour, cv::COLORMAP_TURBO);
  colour.setTo(cv::Scalar(0, 0, 0), scaled == 0);  // invalid disparities black
  writeAtomically(colour, file);
}

}  // namespace occsweep::stereo
