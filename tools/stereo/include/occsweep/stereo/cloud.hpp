// From disparity to a keyframe's point cloud: the stereo camera model, the world frame, the voxel filter
// (core/voxel_filter.hpp, PCL VoxelGrid; its one home, shared with the importers).
#pragma once

#include <cstdint>
#include <vector>

#include <octomap/octomap_types.h>

#include "camera.hpp"
#include "occsweep/core/voxel_filter.hpp"  // voxelFilter, voxelFilterKey

namespace occsweep::stereo {

/// Points of the valid disparities (> 0, OpenCV fixed point 1/16 px) in the world frame:
/// z = fx B / d, x = (u - cx) z / fx, y = (v - cy) z / fx (the rectified pair's Q matrix), then p = R x + t.
/// Depths beyond `max_depth` are dropped (a ZED reports none beyond 20 m).
[[nodiscard]] std::vector<Eigen::Vector3d> reprojectDisparity(const std::vector<std::int16_t>& disparity,
                                                              const StereoCamera& camera, const CameraPose& pose,
                                                              double max_depth);

/// The points unfiltered, in input order (--no-voxel-filter), as the data-set format stores them (float).
[[nodiscard]] std::vector<octomap::point3d> toPoint3d(const std::vector<Eigen::Vector3d>& points);

/// A matcher disparity's cloud prepared once for all its speckle variants (docs/datasets.md, "How generation
/// shares work"). A variant's disparity is the matcher's with some pixels set to -16 (filterSpecklesAsCompute), so
/// its reprojected points are the matcher's points whose pixel it kept, in the same order and with the same
/// values; and voxelFilter, which sums each voxel's points in input order, sums the kept ones in the order of the
/// matcher's points sorted once. Both outputs are bit-identical to the functions above on the variant.
class SharedVoxelFilter {
 public:
  SharedVoxelFilter(const std::vector<std::int16_t>& matcher_disparity, const StereoCamera& camera,
                    const CameraPose& pose, double max_depth, double leaf);
  /// voxelFilter(reprojectDisparity(variant, camera, pose, max_depth), leaf) for a variant of the matcher
  /// disparity: each pixel holds the matcher's value or -16.
  [[nodiscard]] std::vector<octomap::point3d> filtered(const std::vector<std::int16_t>& variant) const;

 private:
  /// reprojectDisparity's points of the matcher disparity in voxelFilter's order: by voxel (z, then y, then x),
  /// then by their order in pixels
  std::vector<Eigen::Vector3d> points_;
  std::vector<std::uint32_t> pixel_;      ///< the pixel each point came from
  std::vector<std::uint32_t> voxel_end_;  ///< each voxel's end in points_, voxels in that order
};

}  // namespace occsweep::stereo
