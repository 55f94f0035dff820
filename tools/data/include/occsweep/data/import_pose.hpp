// Sensor poses of real recordings: `tx ty tz qx qy qz qw` lines or 4x4 matrices, sensor-to-world (docs/import.md).
#pragma once

#include <array>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>
#include <octomap/octomap_types.h>

namespace occsweep {

/// A rigid transform sensor -> world: p_world = R p_sensor + t, in double precision.
struct RigidPose {
  std::array<double, 9> rotation{1, 0, 0, 0, 1, 0, 0, 0, 1};  ///< row-major 3x3
  std::array<double, 3> translation{0, 0, 0};

  /// R p + t in double; apply rounds it to float32.
  [[nodiscard]] std::array<double, 3> applyExact(double x, double y, double z) const;
  [[nodiscard]] octomap::point3d apply(double x, double y, double z) const;
  [[nodiscard]] octomap::point3d origin() const;
  /// The transform the other way: [R^T | -R^T t].
  [[nodiscard]] RigidPose inverse() const;
};

/// Where a reader puts a point it read: pose(x y z) + shift, in double, then rounded to float32 once, so that a
/// far-away (georeferenced) coordinate keeps the digits that --shift brings into range (docs/import.md,
/// "Far-away (georeferenced) clouds"). The default is the identity: the file's own coordinates.
struct CloudPlacement {
  RigidPose pose;
  std::array<double, 3> shift{0, 0, 0};
  [[nodiscard]] octomap::point3d place(double x, double y, double z) const;
  [[nodiscard]] octomap::point3d placeOrigin() const { return place(0, 0, 0); }
};

enum class PoseFormat {
  Quaternion,  ///< one pose a line: tx ty tz qx qy qz qw (slambook order, w last)
  Matrix,      ///< 16 numbers a pose, row-major 4x4, over any number of lines; last row 0 0 0 1
  Tum,         ///< one pose a line: timestamp tx ty tz qx qy qz qw (TUM RGB-D trajectory format, docs/import.md)
  Kitti,       ///< one pose a line: 12 numbers, the 3x4 [R|t] row-major (KITTI odometry poses, docs/import.md)
};

/// The name of a pose format on the command line and in a data set's `source` ("tum"); "quaternion" for today's.
[[nodiscard]] const char* poseFormatName(PoseFormat format);
/// The format of a name; std::invalid_argument listing the names otherwise.
[[nodiscard]] PoseFormat poseFormatNamed(const std::string& name);

/// Which way a pose file's transforms go (docs/import.md, "Poses", --pose-convention): camera (sensor) to world, as
/// occsweep applies them, or world to camera, each pose then read as its inverse.
enum class PoseConvention { CameraToWorld, WorldToCamera };

/// "camera-to-world" or "world-to-camera", on the command line and in a data set's `source.pose_convention`.
[[nodiscard]] const char* poseConventionName(PoseConvention convention);
/// The convention of a name; std::invalid_argument listing the names otherwise.
[[nodiscard]] PoseConvention poseConventionNamed(const std::string& name);

/// How far a quaternion's norm may be from 1 and still be normalised; beyond it the pose is refused, because a
/// quaternion that far off is a corrupted or mis-ordered line, not rounding (docs/import.md).
inline constexpr double kQuaternionNormTolerance = 1e-3;
/// How far R^T R may be from I (max abs entry) and det R from 1 for a matrix pose.
inline constexpr double kRotationTolerance = 1e-3;

/// Rotation of a quaternion (w, x, y, z); `ok` false when |q| is not within kQuaternionNormTolerance of 1.
[[nodiscard]] RigidPose poseFromQuaternion(double tx, double ty, double tz, double qw, double qx, double qy,
                                           double qz, bool& ok);

/// Parses a pose file; `#` comments and blank lines are skipped. DataError naming the line for a wrong column
/// count, NaN or infinite values, a quaternion off unit norm, a matrix that is not a rotation, or no poses.
[[nodiscard]] std::vector<RigidPose> decodePoses(std::string_view text, const std::filesystem::path& file,
                                                 PoseFormat format);
[[nodiscard]] std::vector<RigidPose> readPoses(const std::filesystem::path& file, PoseFormat format);

/// What a data set's source records of its pose files: the file's name, or the list of names of one file per frame.
[[nodiscard]] nlohmann::json poseFileNames(const std::vector<std::filesystem::path>& pose_files);

/// How far apart (seconds) a frame's timestamp and its TUM pose's may be when frames are associated by timestamp:
/// TUM's associate.py default.
inline constexpr double kTumMaxTimeDifference = 0.02;

/// Which poses of one file of a whole sequence the frames take (docs/import.md, "Poses", --pose-start and
/// --pose-step): frame i takes pose start + i step, counting from 0.
struct PoseSelection {
  bool chosen = false;  ///< either flag given (--pose-start 0 alone takes a sequence's first poses)
  std::size_t start = 0, step = 1;
  /// --pose-by-frame-number: each frame takes the pose numbered by the last digits of its file name, counting from 0
  /// (Replica's depth000120.png: pose 120 of traj.txt).
  bool by_frame_number = false;
};

/// Records how the poses were read in a data set's source: `pose_format`, `pose_convention`, and a selection other
/// than the default, `pose_start_step` or `pose_by_frame_number`.
void recordPoseReading(nlohmann::json& source, PoseFormat format, const PoseSelection& selection,
                       PoseConvention convention);

/// The pose of each frame (`frames`: image or cloud files, in order; `kind`: "depth image", "cloud") from
/// `pose_files` (docs/import.md, "Poses"):
/// - one file of one pose per frame, in frame order; with `selection` chosen, one file of a whole sequence (TUM's
///   too, then by position), frame i taking pose start + i step (std::invalid_argument with several files);
/// - one file per frame, each of one pose, in frame order (3DMatch's frame-*.pose.txt);
/// - with `selection.by_frame_number`, one file of a whole sequence, each frame taking the pose its name numbers;
/// - one TUM file (--pose-format tum) of any number of poses, when every frame's name is its timestamp
///   (TUM's depth/1305031102.160407.png): paired as associate.py pairs them, each pose with one frame, the pairs
///   closest in time first, closer than kTumMaxTimeDifference (a frame left without one is refused, where
///   associate.py would drop it).
/// Otherwise a DataError naming the file, the counts and the fix. Poses written world to camera (`convention`) are
/// returned inverted: camera to world.
[[nodiscard]] std::vector<RigidPose> framePoses(const std::vector<std::filesystem::path>& pose_files, PoseFormat format,
                                                const std::vector<std::filesystem::path>& frames,
                                                const std::string& kind, const PoseSelection& selection = {},
                                                PoseConvention convention = PoseConvention::CameraToWorld);

}  // namespace occsweep
