#include "occsweep/stereo/raycast.hpp"

#include <cmath>
#include <limits>

#include "occsweep/core/splitmix64.hpp"
#include "occsweep/stereo/appearance.hpp"

namespace occsweep::stereo {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();

/// Distance along the unit ray to the vertical cylinder of radius r about `c` (the origin is inside it).
double rayCylinderDistance(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Eigen::Vector3d& c, double r) {
  const double qx = o.x() - c.x(), qy = o.y() - c.y();
  const double a = d.x() * d.x() + d.y() * d.y(), b = 2 * (qx * d.x() + qy * d.y()), cc = qx * qx + qy * qy - r * r;
  if (a == 0.0 || cc >= 0.0) return kInf;
  return (-b + std::sqrt(b * b - 4 * a * cc)) / (2 * a);
}

/// The nearest clutter ring the ray meets below the clutter's top, or a Sky hit.
Hit castClutter(const Scene& scene, const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  for (int ring = 0; ring < 4; ++ring) {
    const double t = rayCylinderDistance(o, d, scene.centre, kClutterRings[ring]);
    const Eigen::Vector3d p = o + t * d;
    if (!(t < kInf) || p.z() < 0 || p.z() > clutterTop(scene, ring, p)) continue;
    const Eigen::Vector3d n = Eigen::Vector3d(scene.centre.x() - p.x(), scene.centre.y() - p.y(), 0).normalized();
    return Hit{Surface::Clutter, t, n, ring};
  }
  return Hit{Surface::Sky, kInf, {0, 0, 1}, -1};
}

}  // namespace

ClutterSector clutterSector(const Scene& scene, int ring, const Eigen::Vector3d& p) {
  const double r = kClutterRings[ring];
  const int sectors = int(std::lround(2 * M_PI * r / 8.0));
  const double azimuth = std::atan2(p.y() - scene.centre.y(), p.x() - scene.centre.x());
  const auto index = std::uint64_t(std::floor((azimuth + M_PI) / (2 * M_PI) * sectors)) % std::uint64_t(sectors);
  SplitMix64 rng(scene.seed ^ 0xC1077E4ull ^ (std::uint64_t(ring) << 40) ^ (index * 0x9E3779B97F4A7C15ull));
  const double kind = rng.uniform(), height = rng.uniform(), shade = rng.uniform();
  if (kind < 0.3) return {};
  if (kind < 0.7) return {ClutterSector::Building, 5.0 + 17.0 * height, shade};
  return {ClutterSector::Trees, 6.0 + 6.0 * height, shade};
}

double clutterTop(const Scene& scene, int ring, const Eigen::Vector3d& p) {
  const ClutterSector s = clutterSector(scene, ring, p);
  if (s.kind != ClutterSector::Trees) return s.height;
  const double along = kClutterRings[ring] * std::atan2(p.y() - scene.centre.y(), p.x() - scene.centre.x());
  return s.height + 1.5 * valueNoise(along / 2.0, ring, scene.seed + 501);
}

double rayBoxDistance(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const AxisBox& b) {
  double t0 = 0.0, t1 = kInf;
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0.0) {
      if (o[a] < b.min[a] || o[a] > b.max[a]) return kInf;
      continue;
    }
    double ta = (b.min[a] - o[a]) / d[a], tb = (b.max[a] - o[a]) / d[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return kInf;
  }
  return t0;
}

Hit castRay(const Scene& scene, const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  Hit hit;
  hit.t = kInf;
  if (d.z() < 0) {
    hit = Hit{Surface::Ground, -o.z() / d.z(), {0, 0, 1}, 0};
  }
  for (std::size_t i = 0; i < scene.boxes.size(); ++i) {
    const AxisBox& b = scene.boxes[i];
    const double t = rayBoxDistance(o, d, b);
    if (!(t < hit.t)) continue;
    // The entry face is the one the hit point lies on; pick the axis whose face is nearest the point.
    const Eigen::Vector3d p = o + t * d;
    int axis = 0;
    double best = kInf;
    for (int a = 0; a < 3; ++a) {
      const double gap = std::min(std::abs(p[a] - b.min[a]), std::abs(p[a] - b.max[a]));
      if (gap < best) best = gap, axis = a;
    }
    Eigen::Vector3d n = Eigen::Vector3d::Zero();
    n[axis] = d[axis] > 0 ? -1.0 : 1.0;
    hit = Hit{Surface::Box, t, n, int(i)};
  }
  if (scene.name.environment == Environment::Building) {
    // Walls of a square courtyard around the targets, facing inwards; the camera is always inside.
    const double D = scene.config.facade_distance;
    for (int wall = 0; wall < 4; ++wall) {
      const int axis = wall / 2;
      const double sign = wall % 2 ? -1.0 : 1.0;
      if (d[axis] * sign <= 0) continue;
      const double t = (scene.centre[axis] + sign * D - o[axis]) / d[axis];
      if (!(t < hit.t)) continue;
      const Eigen::Vector3d p = o + t * d;
      if (p.z() < 0 || p.z() > scene.config.facade_height) continue;
      if (std::abs(p[1 - axis] - scene.centre[1 - axis]) > D) continue;
      Eigen::Vector3d n = Eigen::Vector3d::Zero();
      n[axis] = -sign;
      hit = Hit{Surface::Facade, t, n, wall};
    }
  }
  if (scene.config.far_clutter) {
    const Hit far = castClutter(scene, o, d);
    if (far.t < hit.t) hit = far;
  }
  return hit;
}

double surfaceDistance(const Scene& scene, const Eigen::Vector3d& p) {
  double best = std::abs(p.z());  // the ground plane is unbounded
  for (const AxisBox& b : scene.boxes) {
    Eigen::Vector3d outside, inside;
    for (int a = 0; a < 3; ++a) {
      outside[a] = std::max({b.min[a] - p[a], p[a] - b.max[a], 0.0});
      inside[a] = std::min(p[a] - b.min[a], b.max[a] - p[a]);
    }
    best = std::min(best, outside.squaredNorm() > 0 ? outside.norm() : inside.minCoeff());
  }
  if (scene.name.environment == Environment::Building) {
    // Inside the courtyard: distance to the nearest wall; outside it, to the wall's plane (close enough here).
    const double D = scene.config.facade_distance;
    for (int axis = 0; axis < 2; ++axis) best = std::min(best, std::abs(D - std::abs(p[axis] - scene.centre[axis])));
  }
  return best;
}

}  // namespace occsweep::stereo
