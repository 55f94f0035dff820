// CPU rendering of one rectified stereo pair: supersampled ray casting, then a sensor model (shot and read noise
// on linear intensity, gamma 2.2, 8 bits). Per-pixel noise independent between the two images is what makes
// flat colour genuinely hard for stereo (docs/datasets.md).
#pragma once

#include <cstdint>
#include <vector>

#include "camera.hpp"
#include "scene.hpp"

namespace occsweep::stereo {

/// How the right camera's exposure differs from the left's (docs/datasets.md, "Realism and experiment options"):
/// linear intensity x becomes gain * (1 - vignetting r^2) * x before the sensor noise, plus `offset` (black level)
/// after it, encoded with exponent 1 / (2.2 gamma); r is the distance from the principal point, 1 at a corner.
struct RightExposure {
  double gain = 1.0, offset = 0.0, gamma = 1.0, vignetting = 0.0;
  [[nodiscard]] bool isIdentity() const { return gain == 1.0 && offset == 0.0 && gamma == 1.0 && vignetting == 0.0; }
};

struct RenderConfig {
  int supersample = 2;            ///< samples per pixel along each axis (2: 2x2)
  double read_noise = 0.003;      ///< sigma of read noise, linear intensity
  double shot_noise = 2.2e-4;     ///< variance per unit linear intensity: about 2 grey levels at mid-grey
  bool noise = true;
  double noise_scale = 1.0;       ///< multiplies the sigma of read and shot noise together (0: noiseless)
  RightExposure right;            ///< the right image only; identity by default
};

/// Row-major 8-bit grey image.
struct GreyImage {
  int width = 0, height = 0;
  std::vector<std::uint8_t> pixels;
};

struct StereoFrame {
  GreyImage left, right;
  std::vector<std::uint8_t> target_mask;  ///< left pixels whose centre ray hits a box
  std::vector<float> left_depth;          ///< z along the optical axis at left pixel centres; 0 for sky
};

/// Ray direction (world, unit) through pixel (u, v) of a camera at `pose`; u, v may be fractional.
[[nodiscard]] Eigen::Vector3d pixelRay(const StereoCamera& camera, const CameraPose& pose, double u, double v);

/// Renders both images from the true pose. `noise_seed` seeds the sensor noise (left and right differ).
[[nodiscard]] StereoFrame renderFrame(const Scene& scene, const StereoCamera& camera, const CameraPose& pose,
                                      const RenderConfig& config, std::uint64_t noise_seed);

}  // namespace occsweep::stereo
