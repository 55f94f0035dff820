#include "occsweep/stereo/render.hpp"

#include <algorithm>
#include <cmath>

#include "occsweep/core/splitmix64.hpp"
#include "occsweep/stereo/appearance.hpp"
#include "occsweep/stereo/raycast.hpp"

namespace occsweep::stereo {
namespace {

/// Linear intensity -> 8-bit code with the sensor's noise added before gamma (noise lives in the linear domain).
/// `exposure` (the right camera's, else null) scales the signal before the noise and adds the black level after it.
std::uint8_t expose(double linear, const RenderConfig& c, SplitMix64& rng, const RightExposure* exposure,
                    double vignette_r2) {
  const double g = rng.gaussian();  // drawn for every pixel whatever the setting, so sequences never shift
  if (exposure) linear *= exposure->gain * (1.0 - exposure->vignetting * vignette_r2);
  if (c.noise) {
    const double sigma = std::sqrt(c.shot_noise * std::max(linear, 0.0) + c.read_noise * c.read_noise);
    linear += g * (c.noise_scale * sigma);  // 1.0 * sigma is sigma exactly: the default's bytes are unchanged
  }
  if (!exposure) return std::uint8_t(std::lround(255.0 * std::pow(std::clamp(linear, 0.0, 1.0), 1.0 / 2.2)));
  linear += exposure->offset;
  return std::uint8_t(std::lround(255.0 * std::pow(std::clamp(linear, 0.0, 1.0), 1.0 / (2.2 * exposure->gamma))));
}

/// Squared distance of pixel (u, v) from the principal point, 1 at the image corner farthest from it.
double vignetteRadius2(const StereoCamera& cam, int u, int v) {
  const double hx = std::max(cam.cx, cam.width - 1 - cam.cx), hy = std::max(cam.cy, cam.height - 1 - cam.cy);
  return ((u - cam.cx) * (u - cam.cx) + (v - cam.cy) * (v - cam.cy)) / (hx * hx + hy * hy);
}

GreyImage renderEye(const Scene& scene, const StereoCamera& cam, const CameraPose& pose, const RenderConfig& c,
                    std::uint64_t seed, const RightExposure* exposure) {
  GreyImage img{cam.width, cam.height, std::vector<std::uint8_t>(std::size_t(cam.width) * cam.height)};
  SplitMix64 rng(seed);
  const int ss = std::max(1, c.supersample);
  for (int v = 0; v < cam.height; ++v)
    for (int u = 0; u < cam.width; ++u) {
      double sum = 0;
      for (int sy = 0; sy < ss; ++sy)
        for (int sx = 0; sx < ss; ++sx) {
          const double du = (sx + 0.5) / ss - 0.5, dv = (sy + 0.5) / ss - 0.5;
          const Eigen::Vector3d dir = pixelRay(cam, pose, u + du, v + dv);
          const Hit hit = castRay(scene, pose.position, dir);
          // Width one sample covers at the hit, stretched on surfaces seen at a grazing angle.
          const double slant = std::max(std::abs(hit.normal.dot(dir)), 0.2);
          const double footprint = hit.t * (dir.dot(pose.rotation.col(2))) / cam.fx / ss / slant;
          sum += radiance(scene, hit, pose.position, dir, footprint);
        }
      img.pixels[std::size_t(v) * cam.width + u] =
          expose(sum / (ss * ss), c, rng, exposure, exposure ? vignetteRadius2(cam, u, v) : 0.0);
    }
  return img;
}

}  // namespace

Eigen::Vector3d pixelRay(const StereoCamera& cam, const CameraPose& pose, double u, double v) {
  const Eigen::Vector3d in_camera((u - cam.cx) / cam.fx, (v - cam.cy) / cam.fx, 1.0);
  return (pose.rotation * in_camera).normalized();
}

StereoFrame renderFrame(const Scene& scene, const StereoCamera& cam, const CameraPose& pose, const RenderConfig& c,
                        std::uint64_t noise_seed) {
  StereoFrame f;
  CameraPose right = pose;
  right.position = pose.position + cam.baseline * pose.rotation.col(0);
  SplitMix64 seeds(noise_seed);
  const std::uint64_t left_seed = seeds.next(), right_seed = seeds.next();
  f.left = renderEye(scene, cam, pose, c, left_seed, nullptr);
  f.right = renderEye(scene, cam, right, c, right_seed, c.right.isIdentity() ? nullptr : &c.right);
  const std::size_t n = std::size_t(cam.width) * cam.height;
  f.target_mask.assign(n, 0);
  f.left_depth.assign(n, 0.0f);
  for (int v = 0; v < cam.height; ++v)
    for (int u = 0; u < cam.width; ++u) {
      const Eigen::Vector3d dir = pixelRay(cam, pose, u, v);
      const Hit hit = castRay(scene, pose.position, dir);
      const std::size_t i = std::size_t(v) * cam.width + u;
      f.target_mask[i] = hit.surface == Surface::Box;
      if (hit.surface != Surface::Sky) f.left_depth[i] = float(hit.t * dir.dot(pose.rotation.col(2)));
    }
  return f;
}

}  // namespace occsweep::stereo
