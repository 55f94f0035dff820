// Truth voxels as a dense bit per key of a box of keys. Observable truth tests it at every ray step, where a hash
// lookup would cost several times more; truth coverage (truth_coverage.hpp) builds it straight from the truth's
// sources, so that `import truth` of a 60 x 60 x 5 m solid box holds 22 M bits, not an 18 M-key set
// (docs/import.md, "Truth coverage and alignment").
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <octomap/OcTreeKey.h>

#include "ground_truth.hpp"

namespace occsweep {

class TruthMask {
 public:
  /// `keys` over their bounding box.
  explicit TruthMask(const octomap::KeySet& keys);
  /// What `sources` occupy in `frame`'s region (forEachTruthVoxel), over the region's keys: at most
  /// limits().region_voxels bits, which makeGroundTruth checked when it made `frame`.
  TruthMask(const TruthSources& sources, const GroundTruth& frame);

  [[nodiscard]] bool has(const octomap::OcTreeKey& k) const;
  /// The occupied keys.
  [[nodiscard]] std::size_t count() const { return count_; }
  /// `n` occupied keys evenly spaced in key order (x, then y, then z), all of them when fewer.
  [[nodiscard]] std::vector<octomap::OcTreeKey> evenSample(std::size_t n) const;

 private:
  void bound(const octomap::OcTreeKey& lo, const octomap::OcTreeKey& hi);
  void set(const octomap::OcTreeKey& k);
  [[nodiscard]] std::size_t index(const octomap::OcTreeKey& k) const;
  [[nodiscard]] octomap::OcTreeKey keyAt(std::size_t index) const;
  std::array<int, 3> lo_{}, hi_{};
  std::array<std::size_t, 3> size_{};
  std::vector<bool> bits_;
  std::size_t count_ = 0;
};

/// `count` indices spread evenly over [0, n): j * n / count for j < count; all of them when n <= count.
[[nodiscard]] std::vector<std::size_t> evenlySpaced(std::size_t n, std::size_t count);

}  // namespace occsweep
