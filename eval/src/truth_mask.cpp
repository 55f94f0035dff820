#include "occsweep/eval/truth_mask.hpp"

#include <algorithm>

namespace occsweep {

std::vector<std::size_t> evenlySpaced(std::size_t n, std::size_t count) {
  std::vector<std::size_t> at;
  const std::size_t m = std::min(n, count);
  for (std::size_t j = 0; j < m; ++j) at.push_back(std::size_t(std::uint64_t(j) * n / m));
  return at;
}

TruthMask::TruthMask(const octomap::KeySet& keys) {
  octomap::OcTreeKey lo(65535, 65535, 65535), hi(0, 0, 0);
  for (const auto& k : keys)
    for (int i = 0; i < 3; ++i) lo[i] = std::min(lo[i], k[i]), hi[i] = std::max(hi[i], k[i]);
  bound(lo, hi);
  for (const auto& k : keys) set(k);
}

TruthMask::TruthMask(const TruthSources& sources, const GroundTruth& frame) {
  bound(frame.region_min_key, frame.region_max_key);
  forEachTruthVoxel(sources, frame, [this](const octomap::OcTreeKey& k) { set(k); });
}

void TruthMask::bound(const octomap::OcTreeKey& lo, const octomap::OcTreeKey& hi) {
  for (int i = 0; i < 3; ++i) {
    lo_[i] = lo[i], hi_[i] = hi[i];
    size_[i] = std::size_t(std::max(0, hi_[i] - lo_[i] + 1));
  }
  bits_.assign(size_[0] * size_[1] * size_[2], false);
}

void TruthMask::set(const octomap::OcTreeKey& k) {
  auto bit = bits_[index(k)];
  count_ += !bit;
  bit = true;
}

bool TruthMask::has(const octomap::OcTreeKey& k) const {
  for (int i = 0; i < 3; ++i)
    if (k[i] < lo_[i] || k[i] > hi_[i]) return false;
  return bits_[index(k)];
}

std::size_t TruthMask::index(const octomap::OcTreeKey& k) const {
  return (std::size_t(k[0] - lo_[0]) * size_[1] + std::size_t(k[1] - lo_[1])) * size_[2] + std::size_t(k[2] - lo_[2]);
}

octomap::OcTreeKey TruthMask::keyAt(std::size_t index) const {
  const std::size_t z = index % size_[2], y = index / size_[2] % size_[1], x = index / size_[2] / size_[1];
  return octomap::OcTreeKey(octomap::key_type(lo_[0] + int(x)), octomap::key_type(lo_[1] + int(y)),
                            octomap::key_type(lo_[2] + int(z)));
}

// The bits run in key order, so the ordinal of a set bit is that of its key among the sorted occupied keys.
std::vector<octomap::OcTreeKey> TruthMask::evenSample(std::size_t n) const {
  const std::vector<std::size_t> ordinals = evenlySpaced(count_, n);
  std::vector<octomap::OcTreeKey> sample;
  std::size_t ordinal = 0;
  for (std::size_t i = 0; i < bits_.size() && sample.size() < ordinals.size(); ++i)
    if (bits_[i] && ordinal++ == ordinals[sample.size()]) sample.push_back(keyAt(i));
  return sample;
}

}  // namespace occsweep
