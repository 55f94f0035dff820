#include <algorithm>
#include <cmath>
#include <iostream>
#include <stdexcept>

#include "occsweep/eval/coordinates.hpp"
#include "occsweep/io/data_error.hpp"
#include "occsweep/data/import_dataset.hpp"
#include "occsweep/data/import_depth.hpp"
#include "occsweep/data/import_intrinsics.hpp"

namespace occsweep {
namespace fs = std::filesystem;

void validate(const DepthImportConfig& c) {
  auto finite = [](double v) { return std::isfinite(v); };
  if (!finite(c.depth_scale) || c.depth_scale <= 0) throw std::invalid_argument("depth scale must be > 0");
  if (!finite(c.fx) || !finite(c.fy) || c.fx == 0 || c.fy == 0)
    throw std::invalid_argument("intrinsics fx and fy must be finite and non-zero (give --fx --fy --cx --cy)");
  if (!finite(c.cx) || !finite(c.cy)) throw std::invalid_argument("intrinsics cx and cy must be finite");
  if (!finite(c.max_depth) || c.max_depth < 0) throw std::invalid_argument("max depth must be >= 0 (0 = no limit)");
  if (c.stride < 1) throw std::invalid_argument("pixel stride must be >= 1");
}

DepthImportConfig withIntrinsicsFile(DepthImportConfig c, const fs::path& file, bool depth_scale_given) {
  const CameraIntrinsics k = readIntrinsics(file, depth_scale_given);
  c.fx = k.fx, c.fy = k.fy, c.cx = k.cx, c.cy = k.cy;
  if (k.depth_scale && !depth_scale_given) c.depth_scale = *k.depth_scale;
  c.intrinsics_file = file;
  if (k.width && k.height) c.image_width = *k.width, c.image_height = *k.height;
  return c;
}

std::string tooManyPixels(std::uint64_t width, std::uint64_t height) {
  return LimitError("pixels (" + std::to_string(width) + "x" + std::to_string(height) + ")",
                    saturatingProduct(width, height), limits().image_pixels, "--max-image-pixels")
      .what();
}

PinholeView cameraView(const DepthImage& image, const RigidPose& pose, const DepthImportConfig& c) {
  PinholeView view{c.fx, c.fy, c.cx, c.cy, image.width, image.height, pose.rotation};
  // A negative focal length (ICL-NUIM's fy) mirrors the image: recorded as its mirror, focal length > 0 and the
  // principal point reflected (size - 1 - c), which bounds the same pyramid (docs/dataset-format.md, "Sensor views").
  if (view.fx < 0) view.fx = -view.fx, view.cx = image.width - 1 - view.cx;
  if (view.fy < 0) view.fy = -view.fy, view.cy = image.height - 1 - view.cy;
  return view;
}

Scan depthToScan(const DepthImage& image, const RigidPose& pose, const DepthImportConfig& c) {
  const CloudPlacement at{pose, c.shift};
  Scan scan;
  scan.origin = at.placeOrigin();
  scan.view = cameraView(image, pose, c);
  const auto stride = std::size_t(c.stride);
  for (std::size_t v = 0; v < std::size_t(image.height); v += stride)
    for (std::size_t u = 0; u < std::size_t(image.width); u += stride) {
      const std::uint16_t raw = image.values[v * std::size_t(image.width) + u];
      if (raw == 0) continue;  // no measurement
      const double z = raw / c.depth_scale;
      if (c.max_depth > 0 && z >= c.max_depth) continue;
      scan.points.push_back(at.place((double(u) - c.cx) * z / c.fx, (double(v) - c.cy) * z / c.fy, z));
    }
  return scan;
}

namespace {

/// About `cap` of an image's raw values that become points (measured, nearer than --max-depth), evenly spread over
/// its pixels: the sample of the median depth.
void sampleDepths(const DepthImage& image, std::size_t cap, const DepthImportConfig& c,
                  std::vector<std::uint16_t>& sample) {
  const std::size_t step = std::max<std::size_t>(1, image.values.size() / std::max<std::size_t>(cap, 1));
  for (std::size_t i = 0; i < image.values.size(); i += step) {
    const std::uint16_t raw = image.values[i];
    if (raw != 0 && (c.max_depth <= 0 || raw / c.depth_scale < c.max_depth)) sample.push_back(raw);
  }
}

double medianMetres(std::vector<std::uint16_t>& sample, double depth_scale) {
  if (sample.empty()) return 0;
  const auto middle = sample.begin() + std::ptrdiff_t(sample.size() / 2);
  std::nth_element(sample.begin(), middle, sample.end());
  return double(*middle) / depth_scale;
}

/// An image of another size than the intrinsics file's is another camera's, or resized: its pinhole would be wrong.
void requireIntrinsicsSize(const DepthImage& image, const fs::path& file, const DepthImportConfig& c) {
  if (c.image_width == 0 || (image.width == c.image_width && image.height == c.image_height)) return;
  throw DataError(file, "", "is " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                                " pixels, but --intrinsics " + c.intrinsics_file.string() + " is for " +
                                std::to_string(c.image_width) + "x" + std::to_string(c.image_height) +
                                " images: give the intrinsics of this camera and image size");
}

}  // namespace

Dataset importDepthSequence(const std::vector<fs::path>& images, const std::vector<fs::path>& pose_files,
                            const DepthImportConfig& c) {
  validate(c);
  if (images.empty()) throw std::invalid_argument("no depth image given");
  if (pose_files.empty()) throw std::invalid_argument("no pose file given (--poses)");
  const auto poses =
      framePoses(pose_files, c.pose_format, images, "depth image", c.pose_selection, c.pose_convention);
  // About a million values in all (at least one an image), for the median depth that shows a wrong --depth-scale.
  const std::size_t per_image = std::max<std::size_t>(1, 1'000'000 / images.size());
  std::vector<std::uint16_t> depth_sample;
  PointCloudSet scans;
  std::uint64_t total_points = 0;
  nlohmann::json files = nlohmann::json::array(), dropped = nlohmann::json::array();
  ProgressLine progress("depth image");
  for (std::size_t i = 0; i < images.size(); ++i) {
    progress.show(i + 1, images.size());
    const DepthImage image = readDepthImage(images[i]);
    requireIntrinsicsSize(image, images[i], c);
    sampleDepths(image, per_image, c, depth_sample);
    Scan scan = depthToScan(image, poses[i], c);
    files.push_back(images[i].filename().string());
    if (scan.points.empty() && c.skip_empty) {
      dropped.push_back(i);
      continue;
    }
    requireNonEmpty(scan, images[i].string(), "");
    requireFiniteScan(scan, images[i].string(), "",
                      "check --depth-scale, --fx, --fy, --shift and the poses of " + pose_files[0].string());
    countPoints(total_points, scan, images[i].string());
    scans.push_back(std::move(scan));
  }
  if (scans.empty()) throw std::invalid_argument("every depth image is empty");
  nlohmann::json source = {{"generator", "occsweep import depth"},
                           {"images", files},
                           {"poses", poseFileNames(pose_files)},
                           {"depth_scale", c.depth_scale},
                           {"intrinsics", {c.fx, c.fy, c.cx, c.cy}},
                           {"max_depth", c.max_depth},
                           {"stride", c.stride},
                           {"median_depth", medianMetres(depth_sample, c.depth_scale)}};
  if (!c.intrinsics_file.empty()) source["intrinsics_file"] = c.intrinsics_file.filename().string();
  if (!dropped.empty()) source["frames_dropped_empty"] = dropped;  // no part of its inputs (cmd_import.cpp)
  recordPoseReading(source, c.pose_format, c.pose_selection, c.pose_convention);
  return importedDataset(images.front().parent_path().filename().string(), std::move(scans), source);
}

}  // namespace occsweep
