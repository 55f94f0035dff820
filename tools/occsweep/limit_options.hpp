// The flags that raise the limits of occsweep/core/limits.hpp; each command adds those its inputs can reach
// (docs/robustness.md, "Limits and non-regular files").
#pragma once

#include <initializer_list>

#include <CLI/CLI.hpp>

#include "occsweep/core/limits.hpp"

namespace occsweep::cli {

enum class Limit { WindowVoxels, Combinations, RegionVoxels, MapVoxels, ImagePixels, Points, NeighbourDistances,
                   JsonBytes };

inline void addLimitOptions(CLI::App& app, std::initializer_list<Limit> which) {
  Limits& l = limits();
  auto add = [&app](const char* flag, std::uint64_t& value, const char* help) {
    app.add_option(flag, value, help)->capture_default_str()->check(CLI::PositiveNumber)->group("Limits");
  };
  for (Limit limit : which) {
    switch (limit) {
      case Limit::WindowVoxels: add("--max-window-voxels", l.window_voxels, "k-NN: voxels of one scan's key window"); break;
      case Limit::Combinations: add("--max-combinations", l.combinations, "Grid combinations enumerated"); break;
      case Limit::RegionVoxels: add("--max-region-voxels", l.region_voxels, "Voxels of the evaluation region"); break;
      case Limit::MapVoxels: add("--max-map-voxels", l.map_voxels, "Finest-depth voxels of a .ot map read"); break;
      case Limit::ImagePixels: add("--max-image-pixels", l.image_pixels, "Pixels of one depth image"); break;
      case Limit::Points: add("--max-points", l.points, "Points of all scans together"); break;
      case Limit::NeighbourDistances: add("--max-neighbour-distances", l.neighbour_distances, "k nearest of one scan: points x min(k, points - 1)"); break;
      case Limit::JsonBytes: add("--max-json-bytes", l.json_bytes, "Bytes of a JSON file read whole"); break;
    }
  }
}

}  // namespace occsweep::cli
