#include "occsweep/stereo/raycast.hpp"

#include <cmath>
#include <limits>

namespace occsweep::stereo {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
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
