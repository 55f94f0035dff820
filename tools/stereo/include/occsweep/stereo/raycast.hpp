// Analytic ray casting of the scene: boxes, the ground plane z = 0, the courtyard facades, else sky.
#pragma once

#include <Eigen/Core>

#include "scene.hpp"

namespace occsweep::stereo {

enum class Surface { Sky, Ground, Box, Facade };

struct Hit {
  Surface surface = Surface::Sky;
  double t = 0.0;            ///< distance along the unit ray, metres (infinite for sky)
  Eigen::Vector3d normal{0, 0, 1};
  int index = -1;            ///< which box or facade wall
};

/// Slab test: distance along a unit ray from `origin` to the box, +inf when it misses (origin outside).
[[nodiscard]] double rayBoxDistance(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, const AxisBox& box);

/// The nearest surface along the unit ray `dir` from `origin`.
[[nodiscard]] Hit castRay(const Scene& scene, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir);

/// Distance from `p` to the nearest true surface (ground, boxes, facades): how far a cloud point is off the world.
[[nodiscard]] double surfaceDistance(const Scene& scene, const Eigen::Vector3d& p);

}  // namespace occsweep::stereo
