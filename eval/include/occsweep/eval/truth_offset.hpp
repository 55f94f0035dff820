// Whether one rigid translation fits the measured points to the truth's surface clearly better than none
// (docs/import.md, "Truth coverage and alignment"). Poses shifted by a metre still leave most points of a room near
// some other wall or the floor, so the median point-to-truth distance stays small; the share of points on the
// surface with and without the best offset does not: a consistent offset raises it, stereo noise has none to find.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <octomap/octomap_types.h>

#include "truth_mask.hpp"

namespace occsweep {

/// Offsets are searched up to this many voxels along each axis (2 m at 0.1 m); those within kOffsetNearVoxels of
/// none are the "none" they are compared with.
inline constexpr int kOffsetSearchVoxels = 20, kOffsetNearVoxels = 2;
/// Points that vote for offsets (every offset of the search cube, a bit lookup each): the cost's bound.
inline constexpr std::size_t kOffsetVotingPoints = 500;

struct OffsetFit {
  double share_on_surface = 0;         ///< of the points, those within a voxel of a truth surface voxel
  std::array<double, 3> offset{};      ///< metres: the best translation farther than kOffsetNearVoxels voxels
  double offset_share_on_surface = 0;  ///< the same share with every point moved by `offset`
  friend bool operator==(const OffsetFit&, const OffsetFit&) = default;
};

/// The points' share on the truth's surface (a truth voxel of `mask` with a face neighbour outside it, so that a
/// point pushed into a solid box does not count) as they are and moved by the best offset, found by votes of
/// evenly spaced kOffsetVotingPoints of `points` over every offset of the search cube. `points` must not be empty.
[[nodiscard]] OffsetFit bestOffset(const TruthMask& mask, double resolution,
                                   const std::vector<octomap::point3d>& points);

}  // namespace occsweep
