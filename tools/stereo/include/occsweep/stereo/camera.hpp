// A ZED-like rectified stereo pair (0.12 m baseline, fx = 700 px at 1280x720, scaled with the width) and its
// orbit: twice around the targets on a circle inside s_c, keyframes at fixed angular steps.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "occsweep/core/sensor_view.hpp"

namespace occsweep::stereo {

/// Pinhole intrinsics shared by both rectified images. Pixel centres are at integer coordinates (OpenCV).
struct StereoCamera {
  int width = 640, height = 360;
  double fx = 350.0;           ///< focal length, pixels (fx = fy)
  double cx = 319.5, cy = 179.5;
  double baseline = 0.12;      ///< metres, left to right along the camera's x axis
};

/// ZED-like intrinsics at this size: fx = 700 * width / 1280 (about 85 degrees across), centred principal point.
[[nodiscard]] StereoCamera zedLikeCamera(int width, int height);

/// The left camera's pose: p_world = position + rotation * p_camera, camera axes x right, y down, z forward.
struct CameraPose {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
};

/// What the left camera sees from `pose`: its image as a pinhole (fx = fy), the pose's rotation camera -> world.
/// Recorded with every scan (docs/dataset-format.md, "Sensor views").
[[nodiscard]] PinholeView leftCameraView(const StereoCamera& camera, const CameraPose& pose);

/// A camera at `eye` looking at `target`, image x horizontal (z up in the world).
[[nodiscard]] CameraPose lookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target);

struct OrbitConfig {
  int keyframes = 48;          ///< over both orbits
  double radius = 2.6;         ///< metres from the targets' centre, inside s_c = 4 m
  double height = 1.1;         ///< first orbit; the second is `second_orbit_rise` higher and half a step on
  double second_orbit_rise = 0.3;
};

/// Keyframe poses: keyframe k of K at angle 2 pi (2k / K) (+ half a step on the second orbit).
[[nodiscard]] std::vector<CameraPose> orbitPoses(const OrbitConfig& config, const Eigen::Vector3d& target);

/// SLAM-like pose error (docs/datasets.md, "Realism and experiment options"). Drift: a random walk of the position
/// (sigma `metres_per_keyframe` per axis and keyframe) and of the yaw about the world z axis (sigma
/// `yaw_deg_per_keyframe`), about the first keyframe. Jitter: independent per keyframe after the first, not
/// accumulating: position (sigma `jitter_metres` per axis) and a small rotation about the camera centre (sigma
/// `jitter_deg` about each world axis). All 0: the true poses.
struct PoseDrift {
  double metres_per_keyframe = 0.0;
  double yaw_deg_per_keyframe = 0.0;
  double jitter_metres = 0.0;
  double jitter_deg = 0.0;
  std::uint64_t seed = 1;
  [[nodiscard]] bool hasJitter() const { return jitter_metres != 0.0 || jitter_deg != 0.0; }
};

/// The poses a SLAM front end would report for `truth`; the clouds are placed with these.
[[nodiscard]] std::vector<CameraPose> driftedPoses(const std::vector<CameraPose>& truth, const PoseDrift& drift);

}  // namespace occsweep::stereo
