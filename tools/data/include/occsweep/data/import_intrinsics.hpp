// Intrinsics files of public RGB-D recordings, read as downloaded (docs/import.md, "Intrinsics files"): a 3x3
// camera matrix as text (3DMatch's and 7-Scenes' camera-intrinsics.txt) or Replica's cam_params.json.
#pragma once

#include <filesystem>
#include <optional>
#include <string_view>

namespace occsweep {

/// A pinhole camera as a file gives it; what the file does not give is empty.
struct CameraIntrinsics {
  double fx = 0, fy = 0, cx = 0, cy = 0;  ///< pixels; fx, fy finite and non-zero
  std::optional<double> depth_scale;      ///< raw depth units per metre (cam_params.json's "scale")
  std::optional<int> width, height;       ///< the images' size in pixels (cam_params.json's "w", "h"; text: none)
};

/// A JSON object (the first byte that is not a space is `{`): {"camera": {"w", "h", "fx", "fy", "cx", "cy", "scale"
/// (optional only when `depth_scale_given`)}}, cx and cy within 0 to w and h. Otherwise text: 9 numbers, the
/// row-major matrix [fx 0 cx; 0 fy cy; 0 0 1] (its 0s and 1 within 1e-9 of their row's largest entry) over any lines,
/// whole-line `#` comments and blank lines skipped. A leading UTF-8 byte order mark is skipped. DataError naming the
/// file, the line or field, and the rule.
[[nodiscard]] CameraIntrinsics decodeIntrinsics(std::string_view bytes, const std::filesystem::path& file,
                                                bool depth_scale_given);
[[nodiscard]] CameraIntrinsics readIntrinsics(const std::filesystem::path& file, bool depth_scale_given);

}  // namespace occsweep
