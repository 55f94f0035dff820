// The OctoMap baseline (Eq. 4-5): liboctomap itself, never a re-implementation.
#pragma once

#include <memory>

#include <octomap/OcTree.h>

#include "occsweep/core/occupancy_tree.hpp"
#include "occsweep/core/point_cloud_set.hpp"
#include "octomap_parameters.hpp"

namespace occsweep {

/// OctoMap's map of a point cloud set: setProbHit(p_h), setProbMiss(p_m), clamping at p_max and p_min, then
/// insertPointCloud(cloud, origin, s_c) per scan (one update per voxel per scan, occupied wins).
[[nodiscard]] std::unique_ptr<octomap::OcTree> buildOctoMap(const PointCloudSet& set, const OctoMapParams& params);

// ---------------------------------------------------------------------------------------------------------

inline std::unique_ptr<octomap::OcTree> buildOctoMap(const PointCloudSet& set, const OctoMapParams& params) {
  validate(params);
  auto tree = makeTree(params.map.resolution, params.p_max, params.p_min, params.p_t);
  tree->setProbHit(params.p_h);
  tree->setProbMiss(params.p_m);
  octomap::Pointcloud cloud;
  for (const Scan& scan : set) {
    cloud.clear();
    cloud.reserve(scan.points.size());
    for (const auto& p : scan.points) cloud.push_back(p);
    tree->insertPointCloud(cloud, scan.origin, params.map.s_c);
  }
  return tree;
}

}  // namespace occsweep
