// Depth-image sequences (docs/import.md): 16-bit PNG or PGM depth, a depth scale, pinhole intrinsics and one pose a
// frame, turned into scans in the world frame.
#pragma once

#include <array>

#include "occsweep/core/limits.hpp"
#include <cstdint>
#include <filesystem>
#include <string_view>
#include <vector>

#include "occsweep/eval/dataset.hpp"
#include "import_pose.hpp"

namespace occsweep {

struct DepthImage {
  int width = 0, height = 0;
  std::vector<std::uint16_t> values;  ///< row-major, raw sensor units (0 = no measurement)
};

/// Images with more pixels than limits().image_pixels (occsweep/core/limits.hpp) are refused before anything is
/// allocated (a 640x480 frame has 0.3 M): the message of a refusal.
[[nodiscard]] std::string tooManyPixels(std::uint64_t width, std::uint64_t height);

/// 16-bit (or 8-bit) greyscale PNG through libpng. DataError for a bad signature, colour images, a truncated or
/// corrupt stream, or absurd dimensions.
[[nodiscard]] DepthImage decodePng(std::string_view bytes, const std::filesystem::path& file);
/// Netpbm greyscale: P5 (binary, big-endian when maxval > 255) or P2 (ASCII). DataError for a wrong magic, a bad
/// header, a truncated raster, values above maxval, or bytes after the raster.
[[nodiscard]] DepthImage decodePgm(std::string_view bytes, const std::filesystem::path& file);
/// Chooses by the first bytes (PNG signature or `P5`/`P2`).
[[nodiscard]] DepthImage decodeDepthImage(std::string_view bytes, const std::filesystem::path& file);
[[nodiscard]] DepthImage readDepthImage(const std::filesystem::path& file);

/// How depth pixels become points. No defaults for the intrinsics: a wrong guess would silently warp the map.
struct DepthImportConfig {
  double depth_scale = 1000.0;  ///< raw units per metre: depth_m = value / depth_scale (1000 = mm, TUM 5000)
  double fx = 0, fy = 0, cx = 0, cy = 0;  ///< pinhole intrinsics, pixels; fx, fy non-zero (may be negative)
  double max_depth = 0.0;       ///< metres; pixels at or beyond it are dropped (0 = keep all)
  int stride = 1;               ///< use every stride-th pixel in u and v, to keep clouds small
  PoseFormat pose_format = PoseFormat::Quaternion;
  PoseSelection pose_selection;  ///< --pose-start, --pose-step: frame i takes pose start + i step of one file
  PoseConvention pose_convention = PoseConvention::CameraToWorld;  ///< --pose-convention
  bool skip_empty = false;      ///< drop frames without a valid pixel (source.frames_dropped_empty), not refuse
  /// --shift: added to every point and origin after the pose, before the one rounding to float32 (CloudPlacement).
  std::array<double, 3> shift{0, 0, 0};
  /// --intrinsics: the file the intrinsics came from (recorded in source), and the image size it gives, which every
  /// image must have (0: the file gives none).
  std::filesystem::path intrinsics_file;
  int image_width = 0, image_height = 0;
};

/// `config` with the intrinsics of `file` (readIntrinsics), its depth scale too unless `depth_scale_given`, and the
/// image size every image must have when the file gives one.
[[nodiscard]] DepthImportConfig withIntrinsicsFile(DepthImportConfig config, const std::filesystem::path& file,
                                                   bool depth_scale_given);

/// Throws std::invalid_argument naming the field that breaks a rule (scale > 0, fx, fy != 0, stride >= 1...).
void validate(const DepthImportConfig& config);

/// What one frame's camera sees: the image's pinhole (rotation = the pose's), a negative focal length recorded as
/// its mirror (> 0, principal point reflected), which bounds the same pyramid.
[[nodiscard]] PinholeView cameraView(const DepthImage& image, const RigidPose& pose, const DepthImportConfig& config);

/// Back-projects one frame: x = (u - cx) z / fx, y = (v - cy) z / fy, z = value / scale, camera frame (z forward),
/// then moved to the world by `pose`. Zero pixels are skipped. The scan's origin is the camera position, its view
/// cameraView.
[[nodiscard]] Scan depthToScan(const DepthImage& image, const RigidPose& pose, const DepthImportConfig& config);

/// Reads `images` in order, each with its pose from `pose_files` (framePoses: one file, one per image, or a TUM
/// trajectory matched by timestamp); progress on stderr. A data set without ground truth (see importedDataset); its
/// source records the median measured depth in metres (`median_depth`, over up to about a million pixels), which
/// shows a wrong --depth-scale (docs/import.md).
[[nodiscard]] Dataset importDepthSequence(const std::vector<std::filesystem::path>& images,
                                          const std::vector<std::filesystem::path>& pose_files,
                                          const DepthImportConfig& config);
/// Depths a depth camera measures, metres: a median outside is reported as a likely wrong --depth-scale.
inline constexpr double kPlausibleDepthMin = 0.1, kPlausibleDepthMax = 10.0;

}  // namespace occsweep
