// PNG previews for docs/datasets.md, written with libpng's simplified API. Not OpenCV's imgcodecs: on Debian it
// pulls in GDAL, GDCM, TIFF, WebP and OpenJPEG, about 40 MB resident in every occsweep process (measured by
// bench_sweep), for a few preview images.
#include <filesystem>
#include <stdexcept>
#include <unistd.h>

#include <png.h>

#include <opencv2/imgproc.hpp>

#include "occsweep/io/output_file.hpp"
#include "occsweep/eval/png_text.hpp"
#include "occsweep/stereo/generate.hpp"

namespace occsweep::stereo {
namespace {

constexpr const char* kPreviewMark = "occsweep dataset generate";

/// 8-bit grey (CV_8UC1) or OpenCV's BGR (CV_8UC3), written to a temporary name and renamed.
void writeAtomically(const cv::Mat& image, const std::filesystem::path& file) {
  if (!image.isContinuous() || (image.type() != CV_8UC1 && image.type() != CV_8UC3))
    throw std::logic_error("writeAtomically: 8-bit grey or BGR, continuous");
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  png.width = png_uint_32(image.cols);
  png.height = png_uint_32(image.rows);
  png.format = image.channels() == 1 ? PNG_FORMAT_GRAY : PNG_FORMAT_BGR;
  // Encoded in memory, then one checked atomic write (writeFileAtomically).
  png_alloc_size_t size = 0;
  const auto row_stride = png_int_32(image.step[0]);
  if (!png_image_write_to_memory(&png, nullptr, &size, 0, image.data, row_stride, nullptr))
    throw std::runtime_error(file.string() + ": cannot encode the PNG: " + png.message);
  std::string bytes(size, '\0');
  if (!png_image_write_to_memory(&png, bytes.data(), &size, 0, image.data, row_stride, nullptr))
    throw std::runtime_error(file.string() + ": cannot encode the PNG: " + png.message);
  bytes.resize(size);
  // Marked as occsweep's (its Software text chunk), so that a re-run replaces its own preview, never a user's PNG.
  checkOutputTarget(file, true, previewOutput());
  writeFileAtomically(file, pngWithText(bytes, "Software", kPreviewMark));
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

ReplaceableOutput previewOutput() { return markedPngOutput("preview image", kPreviewMark); }

}  // namespace occsweep::stereo
