// Point clouds of real recordings (docs/import.md): PLY (ascii, binary little and big endian), PCD (ascii, binary) and
// plain `x y z` text, one cloud a scan with an optional pose list.
#pragma once

#include <array>
#include <filesystem>
#include <optional>
#include <string_view>
#include <vector>

#include "occsweep/eval/dataset.hpp"
#include "import_pose.hpp"

namespace occsweep {

/// A PLY file's vertices and, when it has a face element, its faces fan-triangulated.
struct PlyData {
  std::vector<octomap::point3d> vertices;
  std::vector<Triangle> triangles;
};

/// DataError for a wrong magic, an unknown format or type, counts the bytes cannot hold, a truncated body, NaN or
/// infinite coordinates, face indices out of range, faces of fewer than 3 vertices, or trailing data.
[[nodiscard]] PlyData decodePly(std::string_view bytes, const std::filesystem::path& file,
                                const CloudPlacement& at = {});

/// PCD v0.7 ascii or binary (binary_compressed is refused). Points whose x, y and z are all NaN are PCL's "no
/// return" in organised clouds: skipped and counted in `skipped_nan`; any other NaN or infinity is an error.
[[nodiscard]] std::vector<octomap::point3d> decodePcd(std::string_view bytes, const std::filesystem::path& file,
                                                      std::size_t* skipped_nan = nullptr,
                                                      const CloudPlacement& at = {});

/// One point a line, `x y z` then optional extra columns (ignored); `#` comments and blank lines skipped.
[[nodiscard]] std::vector<octomap::point3d> decodeXyz(std::string_view bytes, const std::filesystem::path& file,
                                                      const CloudPlacement& at = {});

/// By extension: .ply, .pcd, anything else is `x y z` text.
[[nodiscard]] std::vector<octomap::point3d> decodeCloud(std::string_view bytes, const std::filesystem::path& file,
                                                        const CloudPlacement& at = {});
[[nodiscard]] std::vector<octomap::point3d> readCloud(const std::filesystem::path& file, const CloudPlacement& at = {});

struct CloudImportConfig {
  std::vector<std::filesystem::path> pose_files;  ///< sensor -> world, as framePoses reads them; none: world frame
  PoseFormat pose_format = PoseFormat::Quaternion;
  PoseSelection pose_selection;  ///< --pose-start, --pose-step: frame i takes pose start + i step of one file
  PoseConvention pose_convention = PoseConvention::CameraToWorld;  ///< --pose-convention
  std::array<double, 3> origin{0, 0, 0};           ///< sensor origin of every cloud when there is no pose file
  bool skip_empty = false;  ///< drop empty clouds (source.frames_dropped_empty), not refuse them
  /// --shift: added to every point and origin after the pose, before the one rounding to float32 (CloudPlacement).
  std::array<double, 3> shift{0, 0, 0};
  /// What the sensor sees (docs/import.md, "Sensor views"): a cone whose axis is in the sensor frame (each pose
  /// turns it) or, without a pose file, in the world frame; a half-angle of 180 degrees is every direction. None:
  /// the data set records no view.
  std::optional<ConeView> view;
};

/// The view recorded for a cloud taken with `pose` (sensor -> world): the cone with its axis turned by the pose, or
/// a sphere at 180 degrees. std::invalid_argument naming --view-axis or --view-half-angle when the cone breaks a
/// rule (zero axis, half-angle outside (0, 180]).
[[nodiscard]] SensorView cloudView(const ConeView& cone, const RigidPose& pose);

/// One scan a cloud file, in order; progress on stderr. A data set without ground truth.
[[nodiscard]] Dataset importClouds(const std::vector<std::filesystem::path>& clouds, const CloudImportConfig& config);

}  // namespace occsweep
