// Analytic ray casting of the scene: boxes, the ground plane z = 0, the courtyard facades, else sky.
#pragma once

#include <Eigen/Core>

#include "scene.hpp"

namespace occsweep::stereo {

enum class Surface { Sky, Ground, Box, Facade, Clutter };

struct Hit {
  Surface surface = Surface::Sky;
  double t = 0.0;            ///< distance along the unit ray, metres (infinite for sky)
  Eigen::Vector3d normal{0, 0, 1};
  int index = -1;            ///< which box, facade wall or clutter ring
};

/// Far clutter (SceneConfig::far_clutter): rings of buildings and tree rows around the targets' centre at these
/// radii, each cut into sectors about 8 m wide; a sector is empty, one building or a row of trees.
inline constexpr double kClutterRings[4] = {15.0, 24.0, 38.0, 60.0};
struct ClutterSector {
  enum Kind { Empty, Building, Trees } kind = Empty;
  double height = 0;         ///< building roof or mean tree top, metres
  double shade = 0;          ///< in [0, 1): per-sector albedo variation
};
[[nodiscard]] ClutterSector clutterSector(const Scene& scene, int ring, const Eigen::Vector3d& p);
/// Height of the clutter's top at `p` on ring `ring` (tree tops vary along the row); 0 for an empty sector.
[[nodiscard]] double clutterTop(const Scene& scene, int ring, const Eigen::Vector3d& p);

/// Slab test: distance along a unit ray from `origin` to the box, +inf when it misses (origin outside).
[[nodiscard]] double rayBoxDistance(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, const AxisBox& box);

/// The nearest surface along the unit ray `dir` from `origin`.
[[nodiscard]] Hit castRay(const Scene& scene, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir);

/// Distance from `p` to the nearest true surface (ground, boxes, facades): how far a cloud point is off the world.
[[nodiscard]] double surfaceDistance(const Scene& scene, const Eigen::Vector3d& p);

}  // namespace occsweep::stereo
