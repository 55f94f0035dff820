// The OctoMap baseline (Eq. 4-5): liboctomap itself, never a re-implementation.
#pragma once

#include <memory>

#include <octomap/OcTree.h>

#include "mapping_params.hpp"
#include "point_cloud_set.hpp"

namespace occsweep {

/// An empty OcTree at `resolution` with clamping thresholds and occupancy threshold set.
[[nodiscard]] std::unique_ptr<octomap::OcTree> makeTree(double resolution, double p_max, double p_min, double p_t);

/// OctoMap's map of a point cloud set: setProbHit(p_h), setProbMiss(p_m), clamping at p_max and p_min, then
/// insertPointCloud(cloud, origin, s_c) per scan (one update per voxel per scan, occupied wins).
[[nodiscard]] std::unique_ptr<octomap::OcTree> buildOctoMap(const PointCloudSet& set, const OctoMapParams& params);

// ---------------------------------------------------------------------------------------------------------

inline std::unique_ptr<octomap::OcTree> makeTree(double resolution, double p_max, double p_min, double p_t) {
  auto tree = std::make_unique<octomap::OcTree>(resolution);
  tree->setClampingThresMax(p_max);
  tree->setClampingThresMin(p_min);
  tree->setOccupancyThres(p_t);
  return tree;
}

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
