// Voxel classification against ground truth, and the metrics of the paper's Section 4.4.
#pragma once

#include <cstdint>
#include <vector>

#include <octomap/OcTree.h>

#include "ground_truth.hpp"

namespace occsweep {

/// TP, FP, FN, TN over the region at one threshold.
struct ConfusionCounts {
  std::uint64_t tp = 0, fp = 0, fn = 0, tn = 0;

  [[nodiscard]] double tpr() const;        ///< TP / (TP + FN); NaN when 0/0
  [[nodiscard]] double fdr() const;        ///< FP / (TP + FP); NaN when 0/0
  [[nodiscard]] double precision() const;  ///< TP / (TP + FP); NaN when 0/0
  [[nodiscard]] double fpr() const;        ///< FP / (FP + TN); NaN when 0/0
  friend bool operator==(const ConfusionCounts&, const ConfusionCounts&) = default;
};

/// What the map says about each region voxel: known or not, and its log-odds.
struct RegionSample {
  std::vector<float> positive_log_odds;  ///< log-odds of known voxels that are truly occupied
  std::vector<float> negative_log_odds;  ///< log-odds of known voxels that are truly free
  std::uint64_t positives = 0;           ///< truly occupied region voxels (known or not)
  std::uint64_t negatives = 0;           ///< truly free region voxels (known or not)
};

/// Looks every region voxel up in the map (search(): a voxel it does not find is unknown).
[[nodiscard]] RegionSample sampleRegion(const octomap::OcTree& map, const GroundTruth& truth);

/// Calls visit(key, truly_occupied, node) for every region voxel, x outermost; node is nullptr when unknown.
/// Voxels of truth.excluded are skipped: they are not part of the evaluation.
template <class Visit>
void forEachRegionVoxel(const octomap::OcTree& map, const GroundTruth& truth, Visit&& visit);

/// The rule for one voxel (docs/definitions.md, Occupied at a threshold): known and log-odds >= threshold
/// (l(p_t) in float), as classify() counts it.
[[nodiscard]] inline bool predictedOccupied(const octomap::OcTreeNode* node, float threshold) {
  return node && node->getLogOdds() >= threshold;
}

/// Counts at threshold p_t: predicted occupied when known and log-odds >= l(p_t) in float, as OctoMap's
/// isNodeOccupied; unknown is predicted not occupied (docs/definitions.md, Occupied at a threshold).
[[nodiscard]] ConfusionCounts classify(const RegionSample& sample, double p_t);

/// The same for several thresholds at once (the map does not change with p_t).
[[nodiscard]] std::vector<ConfusionCounts> classify(const RegionSample& sample, const std::vector<double>& p_t);

// ---------------------------------------------------------------------------------------------------------

template <class Visit>
void forEachRegionVoxel(const octomap::OcTree& map, const GroundTruth& truth, Visit&& visit) {
  const auto& lo = truth.region_min_key;
  const auto& hi = truth.region_max_key;
  for (int x = lo[0]; x <= hi[0]; ++x)
    for (int y = lo[1]; y <= hi[1]; ++y)
      for (int z = lo[2]; z <= hi[2]; ++z) {
        const octomap::OcTreeKey key(x, y, z);
        if (!truth.excluded.empty() && truth.excluded.count(key)) continue;
        visit(key, truth.occupied.count(key) > 0, map.search(key));
      }
}

}  // namespace occsweep
