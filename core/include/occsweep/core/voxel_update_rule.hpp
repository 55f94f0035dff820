// The one update of a voxel by one scan (Algorithm 1), shared by the k-NN mapper, its OcTree reference and the
// replay engine (one map, or several maps at once in lanes).
#pragma once

#include <cstdint>

#include "map_settings.hpp"
#include "scan_events.hpp"

namespace occsweep {

/// Which updates a voxel gets from one scan and in what order. `Value` is what one update adds: float for one
/// map, an array of floats for several maps replayed together (sweeps/engine/src/replay_lanes.cpp).
///
/// The order is Algorithm 1's: the hit first (lines 3-10: the clamped sum of the voxel's l(p(s_j))), then l_in
/// when a ray to a point within s_c crossed the voxel (line 11), otherwise l_out when only rays to points beyond
/// s_c did (lines 14-20). The Default variant stops after a hit (OctoMap's "occupied wins": computeUpdate drops a
/// hit voxel from its free cells); Literal applies the miss too (docs/fidelity.md, "An independent check of the
/// k-NN mapper"). OctoMap's own update is the same rule with l_in = l_out = l(p_m) and l(p_h) for a hit.
///
/// Every update goes through `add(delta)`, which the caller supplies for its value type: OctoMap's clamped
/// update, value = clamp(value + delta, l_min, l_max) (OccupancyOcTreeBase::updateNodeLogOdds), done on a float,
/// on every lane, or by OcTree::updateNode itself.
template <class Value>
struct VoxelUpdateRule {
  Value l_in{};   ///< l(p_m): crossed by a ray to a point within s_c
  Value l_out{};  ///< l(p'_m): crossed only by rays to points beyond s_c, cut at s_c
  UpdateVariant variant = UpdateVariant::Default;

  /// Applies one scan's events `flags` (VoxelEventFlags) of one voxel. `hitDelta()` gives the hit's delta and is
  /// called only when the voxel was hit.
  template <class HitDelta, class Add>
  void apply(std::uint8_t flags, HitDelta&& hitDelta, Add&& add) const;
};

// ---------------------------------------------------------------------------------------------------------

template <class Value>
template <class HitDelta, class Add>
inline void VoxelUpdateRule<Value>::apply(std::uint8_t flags, HitDelta&& hitDelta, Add&& add) const {
  if (flags & kHit) {
    add(hitDelta());
    if (variant != UpdateVariant::Literal) return;  // occupied wins
  }
  if (flags & kCrossedIn)
    add(l_in);
  else if (flags & kCrossedOut)
    add(l_out);
}

}  // namespace occsweep
