// The per-data-set split of a grid (Eq. 16) and the contiguous work shards of a sweep.
#pragma once

#include <cstdint>
#include <vector>

namespace occsweep {

/// Seeded permutation of 0..n-1, the same on every platform: SplitMix64(seed) drives Fisher-Yates from the last
/// element down, j = below(i + 1) by rejection sampling (docs/grids.md gives the algorithm in full).
[[nodiscard]] std::vector<std::uint64_t> portablePermutation(std::uint64_t n, std::uint64_t seed);

/// Eq. 16: the permutation split into `groups` contiguous groups, the first n mod groups one longer.
/// Returns the ids of group `index`, in permutation order.
[[nodiscard]] std::vector<std::uint64_t> permutationGroup(std::uint64_t n, std::uint64_t seed, std::uint64_t groups,
                                                          std::uint64_t index);

/// [begin, end) of block `index` of `count` contiguous blocks of n items, the first n mod count one longer.
struct Block {
  std::uint64_t begin = 0, end = 0;
};
[[nodiscard]] Block contiguousBlock(std::uint64_t n, std::uint64_t count, std::uint64_t index);

}  // namespace occsweep
