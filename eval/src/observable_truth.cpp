#include "occsweep/eval/observable_truth.hpp"

#include <algorithm>
#include <stdexcept>

#include <octomap/OcTree.h>

#include "occsweep/core/ray_traversal.hpp"

namespace occsweep {
namespace {

// The truth voxels as a dense bit per key of their bounding box: the blocking test runs at every ray step, where
// a hash lookup would cost several times more. The box lies inside the region, which makeGroundTruth has bounded
// by limits().region_voxels, so it holds at most that many bits.
class TruthMask {
 public:
  explicit TruthMask(const octomap::KeySet& keys) {
    lo_ = {65535, 65535, 65535}, hi_ = {0, 0, 0};
    for (const auto& k : keys)
      for (int i = 0; i < 3; ++i) lo_[i] = std::min<int>(lo_[i], k[i]), hi_[i] = std::max<int>(hi_[i], k[i]);
    for (int i = 0; i < 3; ++i) size_[i] = std::size_t(std::max(0, hi_[i] - lo_[i] + 1));
    bits_.assign(size_[0] * size_[1] * size_[2], false);
    for (const auto& k : keys) bits_[index(k)] = true;
  }
  [[nodiscard]] bool has(const octomap::OcTreeKey& k) const {
    for (int i = 0; i < 3; ++i)
      if (k[i] < lo_[i] || k[i] > hi_[i]) return false;
    return bits_[index(k)];
  }

 private:
  [[nodiscard]] std::size_t index(const octomap::OcTreeKey& k) const {
    return (std::size_t(k[0] - lo_[0]) * size_[1] + std::size_t(k[1] - lo_[1])) * size_[2] + std::size_t(k[2] - lo_[2]);
  }
  std::array<int, 3> lo_{}, hi_{};
  std::array<std::size_t, 3> size_{};
  std::vector<bool> bits_;
};

// True when the ray from `origin` to the centre of `key` stays within s_c and visits no truth voxel.
bool seenFrom(const octomap::OcTree& grid, const TruthMask& mask, const octomap::point3d& origin,
              const octomap::OcTreeKey& key, double s_c) {
  const octomap::point3d centre = grid.keyToCoord(key);
  if (!(double((centre - origin).norm()) <= s_c)) return false;
  bool blocked = false;
  const bool traversed = traverseRay(grid, origin, centre, [&](const octomap::OcTreeKey& k) {
    blocked = mask.has(k);
    return !blocked;
  });
  return traversed && !blocked;
}

}  // namespace

const char* truthModeName(TruthMode mode) { return mode == TruthMode::Observable ? "observable" : "full"; }

TruthMode parseTruthMode(const std::string& name) {
  if (name == "full") return TruthMode::Full;
  if (name == "observable") return TruthMode::Observable;
  throw std::invalid_argument("truth '" + name + "': must be full or observable");
}

octomap::KeySet observableTruthVoxels(const GroundTruth& truth, const std::vector<octomap::point3d>& origins,
                                      double s_c) {
  octomap::KeySet seen;
  if (truth.occupied.empty()) return seen;
  const octomap::OcTree grid(truth.resolution);
  const TruthMask mask(truth.occupied);
  for (const auto& key : truth.occupied)
    for (const auto& origin : origins)
      if (seenFrom(grid, mask, origin, key, s_c)) {
        seen.insert(key);
        break;
      }
  return seen;
}

GroundTruth restrictToObservable(GroundTruth truth, const std::vector<octomap::point3d>& origins, double s_c) {
  const octomap::KeySet seen = observableTruthVoxels(truth, origins, s_c);
  truth.excluded.clear();
  for (const auto& key : truth.occupied)
    if (!seen.count(key)) truth.excluded.insert(key);
  return truth;
}

GroundTruth evaluatedTruth(TruthMode mode, GroundTruth full, const PointCloudSet& set, double s_c) {
  if (mode == TruthMode::Full) return full;
  std::vector<octomap::point3d> origins;
  origins.reserve(set.size());
  for (const Scan& scan : set) origins.push_back(scan.origin);
  return restrictToObservable(std::move(full), origins, s_c);
}

}  // namespace occsweep
