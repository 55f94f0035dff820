// An open-addressing hash index from voxel keys to dense indices: the hot path of ray traversal, several times
// faster than octomap::KeySet (std::unordered_set), and cleared in time proportional to what it holds.
#pragma once

#include <cstdint>
#include <vector>

#include <octomap/OcTreeKey.h>

namespace occsweep {

class FlatKeyIndex {
 public:
  /// The dense index of `key`, inserting it with index size() when new.
  std::uint32_t findOrInsert(const octomap::OcTreeKey& key);
  [[nodiscard]] std::uint32_t size() const { return std::uint32_t(used_.size()); }
  void clear();

  [[nodiscard]] static std::uint64_t pack(const octomap::OcTreeKey& k) {
    return (std::uint64_t(k[0]) << 32) | (std::uint64_t(k[1]) << 16) | std::uint64_t(k[2]);
  }

 private:
  [[nodiscard]] static std::size_t home(std::uint64_t packed, std::size_t mask) {
    return std::size_t((packed * 0x9E3779B97F4A7C15ull) >> 20) & mask;
  }
  void grow();

  std::vector<std::uint64_t> keys_;    // packed key + 1; 0 marks an empty slot
  std::vector<std::uint32_t> values_;
  std::vector<std::uint32_t> used_;    // occupied slots, in insertion order
};

// ---------------------------------------------------------------------------------------------------------

inline void FlatKeyIndex::clear() {
  for (std::uint32_t s : used_) keys_[s] = 0;
  used_.clear();
}

inline void FlatKeyIndex::grow() {
  std::vector<std::uint64_t> keys(std::max<std::size_t>(1024, keys_.size() * 2), 0);
  std::vector<std::uint32_t> values(keys.size());
  const std::size_t mask = keys.size() - 1;
  for (std::uint32_t& s : used_) {
    std::size_t i = home(keys_[s], mask);
    while (keys[i]) i = (i + 1) & mask;
    keys[i] = keys_[s];
    values[i] = values_[s];
    s = std::uint32_t(i);
  }
  keys_.swap(keys);
  values_.swap(values);
}

inline std::uint32_t FlatKeyIndex::findOrInsert(const octomap::OcTreeKey& key) {
  if ((used_.size() + 1) * 2 > keys_.size()) grow();  // at most half full: short probe runs
  const std::uint64_t packed = pack(key) + 1;
  const std::size_t mask = keys_.size() - 1;
  std::size_t i = home(packed, mask);
  while (keys_[i]) {
    if (keys_[i] == packed) return values_[i];
    i = (i + 1) & mask;
  }
  keys_[i] = packed;
  values_[i] = std::uint32_t(used_.size());
  used_.push_back(std::uint32_t(i));
  return values_[i];
}

}  // namespace occsweep
