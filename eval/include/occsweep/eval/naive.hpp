// The naive approach (docs/definitions.md, Naive approach): a voxel is occupied when it holds at least
// one point of the point cloud set. No rays, no probabilities. Used to rank point cloud sets by FDR.
#pragma once

#include "occsweep/core/point_cloud_set.hpp"
#include "confusion.hpp"
#include "ground_truth.hpp"

namespace occsweep {

/// Counts over the region at the truth's resolution: a region voxel holding a point is predicted occupied, every
/// other region voxel free. Points outside OctoMap's key range or the region count for nothing.
[[nodiscard]] ConfusionCounts naiveConfusion(const PointCloudSet& set, const GroundTruth& truth);

}  // namespace occsweep
