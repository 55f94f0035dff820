// The map every method builds: a liboctomap OcTree, so that any map is written as .ot and classified alike.
#pragma once

#include <memory>

#include <octomap/OcTree.h>

namespace occsweep {

/// An empty OcTree at `resolution` with clamping thresholds and occupancy threshold set.
[[nodiscard]] inline std::unique_ptr<octomap::OcTree> makeTree(double resolution, double p_max, double p_min,
                                                               double p_t) {
  auto tree = std::make_unique<octomap::OcTree>(resolution);
  tree->setClampingThresMax(p_max);
  tree->setClampingThresMin(p_min);
  tree->setOccupancyThres(p_t);
  return tree;
}

}  // namespace occsweep
