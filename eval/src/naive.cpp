#include "occsweep/eval/naive.hpp"

#include <octomap/OcTree.h>

namespace occsweep {

ConfusionCounts naiveConfusion(const PointCloudSet& set, const GroundTruth& truth) {
  const octomap::OcTree grid(truth.resolution);  // the same key arithmetic as the truth and the maps
  octomap::KeySet predicted;
  for (const Scan& scan : set)
    for (const auto& p : scan.points) {
      octomap::OcTreeKey key;
      if (grid.coordToKeyChecked(p, key) && truth.inRegion(key)) predicted.insert(key);
    }
  ConfusionCounts c;
  for (const auto& key : predicted)
    if (!truth.excluded.count(key)) (truth.occupied.count(key) ? c.tp : c.fp) += 1;  // excluded: not evaluated
  c.fn = truth.evaluatedTrueVoxelCount() - c.tp;
  c.tn = truth.evaluatedVoxelCount() - c.tp - c.fp - c.fn;
  return c;
}

}  // namespace occsweep
