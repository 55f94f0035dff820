// Reading a map voxel by voxel at its finest resolution, whatever OctoMap pruned.
#pragma once

#include <unordered_map>

#include <octomap/OcTree.h>

namespace occsweep {

using VoxelLogOdds = std::unordered_map<octomap::OcTreeKey, float, octomap::OcTreeKey::KeyHash>;

/// Calls fn(key, log_odds) for every known voxel at the finest level; a pruned leaf stands for all its voxels.
template <class Fn>
void forEachVoxel(const octomap::OcTree& tree, Fn&& fn);

/// Every known voxel's log-odds, keyed at the finest level: the form in which two maps compare voxel for voxel.
[[nodiscard]] VoxelLogOdds voxelLogOdds(const octomap::OcTree& tree);

// ---------------------------------------------------------------------------------------------------------

template <class Fn>
void forEachVoxel(const octomap::OcTree& tree, Fn&& fn) {
  const unsigned depth = tree.getTreeDepth();
  for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it) {
    const unsigned level = depth - it.getDepth();
    const octomap::OcTreeKey base = it.getIndexKey();
    const unsigned span = 1u << level;
    const float value = it->getLogOdds();
    for (unsigned x = 0; x < span; ++x)
      for (unsigned y = 0; y < span; ++y)
        for (unsigned z = 0; z < span; ++z)
          fn(octomap::OcTreeKey(base[0] + x, base[1] + y, base[2] + z), value);
  }
}

inline VoxelLogOdds voxelLogOdds(const octomap::OcTree& tree) {
  VoxelLogOdds out;
  forEachVoxel(tree, [&](const octomap::OcTreeKey& k, float v) { out.emplace(k, v); });
  return out;
}

}  // namespace occsweep
