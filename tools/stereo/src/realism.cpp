#include "occsweep/stereo/realism.hpp"

#include <cmath>
#include <stdexcept>

namespace occsweep::stereo {

PoseDrift orbslam2PoseError(int keyframes) {
  if (keyframes < 2) throw std::invalid_argument("--pose-error orbslam2 needs at least 2 keyframes");
  // Degrees of rotation error per metre of translation error, from the KITTI medians (0.23 deg per 0.70 m).
  const double deg_per_metre = kOrbSlam2KittiRotDegPer100m / kOrbSlam2KittiTransPercent;
  const double share = kOrbSlam2EurocAteMetres / std::sqrt(2.0);  // RMS (3D) of jitter, and of drift
  PoseDrift p;
  // Jitter: sqrt(3) sigma = share; its rotation angle, sqrt(3) sigma_deg = deg_per_metre * share.
  p.jitter_metres = share / std::sqrt(3.0);
  p.jitter_deg = deg_per_metre * p.jitter_metres;
  // Drift, a random walk: E|offset_k|^2 = 3 sigma^2 k, whose mean over k = 0..K-1 is 3 sigma^2 (K - 1) / 2 = share^2.
  p.metres_per_keyframe = share / std::sqrt(1.5 * (keyframes - 1));
  // Yaw walk: its RMS, sigma_yaw sqrt((K - 1) / 2), is deg_per_metre times the drift's RMS.
  p.yaw_deg_per_keyframe = deg_per_metre * std::sqrt(3.0) * p.metres_per_keyframe;
  return p;
}

RightExposure exposureMismatchPreset() { return RightExposure{1.06, 0.002, 1.03, 0.10}; }

nlohmann::json realismOptionsJson(const GenerateConfig& c) {
  nlohmann::json j = nlohmann::json::object();
  const PoseDrift& d = c.drift;
  // Drift alone counts too: ranking.json's options are what `reproduce` tells data sets apart by.
  if (d.metres_per_keyframe != 0.0 || d.yaw_deg_per_keyframe != 0.0 || d.hasJitter() || !c.presets.pose_error.empty())
    j["pose_error"] = {{"preset", c.presets.pose_error}, {"drift_metres_per_keyframe", d.metres_per_keyframe},
                       {"drift_yaw_deg_per_keyframe", d.yaw_deg_per_keyframe}, {"jitter_metres", d.jitter_metres},
                       {"jitter_deg", d.jitter_deg}};
  const RightExposure& e = c.render.right;
  if (!e.isIdentity() || !c.presets.exposure.empty())
    j["right_exposure"] = {{"preset", c.presets.exposure}, {"gain", e.gain}, {"offset", e.offset},
                           {"gamma", e.gamma}, {"vignetting", e.vignetting}};
  if (c.scene.far_clutter) j["far_clutter"] = true;
  if (c.scene.box_height != SceneConfig{}.box_height) j["box_height"] = c.scene.box_height;
  if (!c.voxel_filter) j["voxel_filter"] = false;
  if (c.render.noise_scale != 1.0) j["noise_scale"] = c.render.noise_scale;
  if (c.presets.realistic) j["realistic"] = true;
  return j;
}

}  // namespace occsweep::stereo
