// Ground truth at the map's resolution: occupied voxel keys inside an evaluation region
// (docs/definitions.md, Ground truth and evaluation region).
#pragma once

#include <array>
#include <vector>

#include <cstddef>
#include <cstdint>
#include <functional>

#include <octomap/OcTreeKey.h>
#include <octomap/octomap_types.h>

namespace occsweep {

/// An axis-aligned box, metres.
struct AxisBox {
  std::array<double, 3> min{};
  std::array<double, 3> max{};
};

struct Triangle {
  std::array<octomap::point3d, 3> v;
};

/// Where the truth comes from; any mix of the three sources (docs/definitions.md, Ground truth and evaluation region).
struct TruthSources {
  std::vector<AxisBox> boxes;             ///< a voxel is occupied when its cube overlaps a box (positive volume)
  std::vector<Triangle> mesh;             ///< voxels a triangle passes through (touching counts)
  std::vector<octomap::point3d> points;   ///< the voxel holding each point
};

/// Occupied keys and the region's keys at one resolution. A voxel belongs to the region when its centre lies
/// in the region box (borders included); voxels outside count for nothing.
struct GroundTruth {
  double resolution = 0.1;
  AxisBox region;
  octomap::OcTreeKey region_min_key, region_max_key;  ///< inclusive key bounds of the region
  octomap::KeySet occupied;                           ///< only keys inside the region
  /// Truth voxels (a subset of `occupied`) that leave the evaluation, counted neither as positive nor as
  /// negative: the unobservable ones under observable truth (observable_truth.hpp); empty under full truth.
  octomap::KeySet excluded;

  [[nodiscard]] bool inRegion(const octomap::OcTreeKey& k) const;
  [[nodiscard]] std::size_t regionVoxelCount() const;
  /// What an evaluation counts, the excluded voxels left out: TP+FP+FN+TN and TP+FN of every threshold.
  [[nodiscard]] std::size_t evaluatedVoxelCount() const { return regionVoxelCount() - excluded.size(); }
  [[nodiscard]] std::size_t evaluatedTrueVoxelCount() const { return occupied.size() - excluded.size(); }
};

/// Rasterises the sources at `resolution` with OctoMap's key arithmetic. Throws std::invalid_argument for an
/// empty or inverted region, or a non-positive resolution.
/// Throws LimitError (occsweep/core/limits.hpp) when the region holds more than limits().region_voxels voxels,
/// before allocating anything.
[[nodiscard]] GroundTruth makeGroundTruth(const TruthSources& sources, const AxisBox& region, double resolution);

/// Calls `visit` with each key the sources occupy inside `frame`'s region at its resolution (a key two sources
/// occupy comes twice): makeGroundTruth's rasterisation, for a caller that needs no key set (truth_mask.hpp).
void forEachTruthVoxel(const TruthSources& sources, const GroundTruth& frame,
                       const std::function<void(const octomap::OcTreeKey&)>& visit);

/// Voxels whose centre lies in `region` at `resolution` (the count makeGroundTruth checks), 0 when none;
/// UINT64_MAX when the region reaches beyond OctoMap's 16-bit keys at this resolution.
[[nodiscard]] std::uint64_t regionVoxelCount(const AxisBox& region, double resolution);

/// Separating-axis test of a triangle against an axis-aligned cube (Akenine-Moeller 2001), closed sets.
[[nodiscard]] bool triangleTouchesBox(const Triangle& t, const std::array<double, 3>& centre, double half);

}  // namespace occsweep
