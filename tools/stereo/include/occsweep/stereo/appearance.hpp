// What the camera sees at a hit: procedural albedo (cardboard, Voronoi lines, asphalt, parking markings, brick
// facades), Lambertian shading from a fixed sun plus a weak fill light, and a smooth, textureless sky (with far clutter: soft
// clouds, and buildings and trees 15-60 m away, docs/datasets.md "Realism and experiment options").
// Texture detail fades with the pixel footprint (an analytic box filter): without it, detail finer than a
// pixel aliases differently in the left and right images and adds texture that is not there.
#pragma once

#include <cstdint>

#include <Eigen/Core>

#include "raycast.hpp"

namespace occsweep::stereo {

/// Linear radiance in [0, 1] of a ray's hit. `footprint` is the width one sample covers at the hit, metres.
[[nodiscard]] double radiance(const Scene& scene, const Hit& hit, const Eigen::Vector3d& origin,
                              const Eigen::Vector3d& dir, double footprint);

/// Value noise in [-1, 1] on a unit lattice, smooth between lattice points (portable integer hash).
[[nodiscard]] double valueNoise(double x, double y, std::uint64_t seed);

/// Distance from (x, y) to the nearest Voronoi border of jittered feature points, one per unit cell.
[[nodiscard]] double voronoiBorderDistance(double x, double y, std::uint64_t seed);

}  // namespace occsweep::stereo
