// The built-in scene: the main job's data on a fresh machine, no download.
#pragma once

#include <cstdint>

#include "dataset.hpp"

namespace occsweep {

/// Four 0.5 m boxes in an O layout on a ground plane, a simulated depth sensor orbiting them twice,
/// Gaussian range noise and a few percent outliers. Deterministic from the seed.
struct BuiltinSceneConfig {
  std::uint64_t seed = 1;
  int scans = 24;                 ///< keyframes over both orbits
  int width = 64;                 ///< rays per row
  int height = 48;                ///< rows
  double fov_horizontal_deg = 70.0;
  double orbit_radius = 2.6;      ///< metres from the layout's centre, inside s_c = 4 m
  double sensor_height = 1.1;     ///< first orbit; the second is 0.3 m higher
  double noise_sigma = 0.02;      ///< Gaussian range noise, metres
  double outlier_fraction = 0.03; ///< returns replaced by a uniform range between 0.3 m and the true one
  double max_return = 8.0;        ///< no return beyond this range: rays past s_c exercise z_out
  double box_edge = 0.5;
};

[[nodiscard]] Dataset makeBuiltinScene(const BuiltinSceneConfig& config = {});

}  // namespace occsweep
