#include "occsweep/stereo/camera.hpp"

#include <cmath>

#include <Eigen/Geometry>

#include "occsweep/core/splitmix64.hpp"

namespace occsweep::stereo {

StereoCamera zedLikeCamera(int width, int height) {
  StereoCamera c;
  c.width = width;
  c.height = height;
  c.fx = 700.0 * width / 1280.0;
  c.cx = (width - 1) / 2.0;
  c.cy = (height - 1) / 2.0;
  return c;
}

PinholeView leftCameraView(const StereoCamera& camera, const CameraPose& pose) {
  const Eigen::Matrix3d& r = pose.rotation;
  return PinholeView{camera.fx, camera.fx, camera.cx, camera.cy, camera.width, camera.height,
                     {r(0, 0), r(0, 1), r(0, 2), r(1, 0), r(1, 1), r(1, 2), r(2, 0), r(2, 1), r(2, 2)}};
}

CameraPose lookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target) {
  const Eigen::Vector3d forward = (target - eye).normalized();
  const Eigen::Vector3d right = forward.cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d down = forward.cross(right);
  CameraPose pose;
  pose.position = eye;
  pose.rotation.col(0) = right;
  pose.rotation.col(1) = down;
  pose.rotation.col(2) = forward;
  return pose;
}

std::vector<CameraPose> orbitPoses(const OrbitConfig& c, const Eigen::Vector3d& target) {
  std::vector<CameraPose> poses;
  const int per_orbit = (c.keyframes + 1) / 2;
  for (int k = 0; k < c.keyframes; ++k) {
    const int orbit = k < per_orbit ? 0 : 1;
    const int step = k - orbit * per_orbit;
    const double angle = 2.0 * M_PI * (step + 0.5 * orbit) / per_orbit;
    const Eigen::Vector3d eye(target.x() + c.radius * std::cos(angle), target.y() + c.radius * std::sin(angle),
                              c.height + orbit * c.second_orbit_rise);
    poses.push_back(lookAt(eye, target));
  }
  return poses;
}

namespace {

/// Jitter on top of the drifted poses, from its own random stream: turning jitter on never shifts the drift's.
std::vector<CameraPose> jittered(std::vector<CameraPose> poses, const PoseDrift& drift) {
  SplitMix64 rng(drift.seed ^ 0x7177E5ull);
  for (std::size_t k = 0; k < poses.size(); ++k) {
    Eigen::Vector3d dp, dr;
    for (int a = 0; a < 3; ++a) dp[a] = rng.gaussian();
    for (int a = 0; a < 3; ++a) dr[a] = rng.gaussian();
    if (k == 0) continue;  // the first keyframe defines the map frame of a SLAM system
    poses[k].position += drift.jitter_metres * dp;
    const Eigen::Vector3d angle = drift.jitter_deg * M_PI / 180.0 * dr;
    if (angle.norm() > 0)
      poses[k].rotation = Eigen::AngleAxisd(angle.norm(), angle.normalized()).toRotationMatrix() * poses[k].rotation;
  }
  return poses;
}

}  // namespace

std::vector<CameraPose> driftedPoses(const std::vector<CameraPose>& truth, const PoseDrift& drift) {
  if (drift.hasJitter()) {
    PoseDrift drift_only = drift;
    drift_only.jitter_metres = drift_only.jitter_deg = 0.0;
    return jittered(driftedPoses(truth, drift_only), drift);
  }
  if (drift.metres_per_keyframe == 0.0 && drift.yaw_deg_per_keyframe == 0.0) return truth;
  SplitMix64 rng(drift.seed);
  std::vector<CameraPose> out;
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  double yaw = 0.0;
  for (std::size_t k = 0; k < truth.size(); ++k) {
    // Draw every number for every keyframe so one setting never shifts the other's sequence.
    const double gx = rng.gaussian(), gy = rng.gaussian(), gz = rng.gaussian(), gyaw = rng.gaussian();
    if (k > 0) {
      offset += drift.metres_per_keyframe * Eigen::Vector3d(gx, gy, gz);
      yaw += drift.yaw_deg_per_keyframe * M_PI / 180.0 * gyaw;
    }
    // Drift about the first keyframe: rotate the path and the camera about z through the first position.
    const Eigen::Matrix3d rz = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    CameraPose p;
    p.position = truth[0].position + rz * (truth[k].position - truth[0].position) + offset;
    p.rotation = rz * truth[k].rotation;
    out.push_back(p);
  }
  return out;
}

}  // namespace occsweep::stereo
