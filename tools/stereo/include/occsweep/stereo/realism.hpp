// Presets of the generator's realism options and how every option used is recorded (docs/datasets.md, "Realism and
// experiment options"): keyframe pose error like ORB-SLAM2 on a stereo camera, exposure differences between the
// two cameras, far clutter, and the experiment knobs (box height, voxel filter, noise scale).
#pragma once

#include <nlohmann/json.hpp>

#include "generate.hpp"

namespace occsweep::stereo {

/// ORB-SLAM2 stereo accuracy (Mur-Artal & Tardos, IEEE T-RO 33(5), 2017). Table II, EuRoC: absolute translation
/// RMSE of the 10 sequences it tracks, 0.018-0.119 m, median 0.035 m. Table I, KITTI 00-10: median relative
/// translation error 0.70 % and rotation error 0.23 deg / 100 m.
inline constexpr double kOrbSlam2EurocAteMetres = 0.035;
inline constexpr double kOrbSlam2KittiTransPercent = 0.70;
inline constexpr double kOrbSlam2KittiRotDegPer100m = 0.23;

/// `--pose-error orbslam2` for an orbit of `keyframes` keyframes: the RMS position error over the keyframes equals
/// the EuRoC median ATE, half its variance from jitter and half from drift; rotation error is the KITTI ratio
/// (0.23 deg per 0.70 m) times the translation error. Derivation: docs/datasets.md.
[[nodiscard]] PoseDrift orbslam2PoseError(int keyframes);

/// `--exposure mismatch`: the right camera 6 % brighter, black level +0.002, gamma 1.03, 10 % more vignetting at
/// the corners. Our assumption (no published figure for a ZED's left/right mismatch was found), docs/datasets.md.
[[nodiscard]] RightExposure exposureMismatchPreset();

/// The options that differ from the defaults, with their numbers and presets; an empty object when none does
/// (so a default data set's manifest and ranking are byte-identical to those made before the options existed).
[[nodiscard]] nlohmann::json realismOptionsJson(const GenerateConfig& config);

}  // namespace occsweep::stereo
