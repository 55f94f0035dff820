// From disparity to a keyframe's point cloud: the stereo camera model, the world frame, a 0.1 m voxel filter.
#pragma once

#include <cstdint>
#include <vector>

#include <octomap/octomap_types.h>

#include "camera.hpp"

namespace occsweep::stereo {

/// Points of the valid disparities (> 0, OpenCV fixed point 1/16 px) in the world frame:
/// z = fx B / d, x = (u - cx) z / fx, y = (v - cy) z / fx (the rectified pair's Q matrix), then p = R x + t.
/// Depths beyond `max_depth` are dropped (a ZED reports none beyond 20 m).
[[nodiscard]] std::vector<Eigen::Vector3d> reprojectDisparity(const std::vector<std::int16_t>& disparity,
                                                              const StereoCamera& camera, const CameraPose& pose,
                                                              double max_depth);

/// PCL VoxelGrid semantics: voxel index floor(p / leaf) per axis, one point per occupied voxel at the centroid
/// of its points; output ordered by voxel (z, then y, then x), so the result does not depend on input order.
[[nodiscard]] std::vector<octomap::point3d> voxelFilter(const std::vector<Eigen::Vector3d>& points, double leaf);

/// The points unfiltered, in input order (--no-voxel-filter), as the data-set format stores them (float).
[[nodiscard]] std::vector<octomap::point3d> toPoint3d(const std::vector<Eigen::Vector3d>& points);

}  // namespace occsweep::stereo
