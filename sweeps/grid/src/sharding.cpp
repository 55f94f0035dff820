#include "occsweep/sweeps/sharding.hpp"

#include <numeric>
#include <stdexcept>
#include <utility>

#include "occsweep/core/splitmix64.hpp"

namespace occsweep {

std::vector<std::uint64_t> portablePermutation(std::uint64_t n, std::uint64_t seed) {
  std::vector<std::uint64_t> p(n);
  std::iota(p.begin(), p.end(), std::uint64_t(0));
  SplitMix64 rng(seed);
  for (std::uint64_t i = n; i > 1; --i) std::swap(p[i - 1], p[rng.below(i)]);  // Fisher-Yates, last to first
  return p;
}

Block contiguousBlock(std::uint64_t n, std::uint64_t count, std::uint64_t index) {
  if (count == 0 || index >= count) throw std::invalid_argument("block index must be < block count");
  const std::uint64_t base = n / count, extra = n % count;
  Block b;
  b.begin = index * base + std::min(index, extra);
  b.end = b.begin + base + (index < extra ? 1 : 0);
  return b;
}

std::vector<std::uint64_t> permutationGroup(std::uint64_t n, std::uint64_t seed, std::uint64_t groups,
                                            std::uint64_t index) {
  const auto perm = portablePermutation(n, seed);
  const Block b = contiguousBlock(n, groups, index);
  return {perm.begin() + long(b.begin), perm.begin() + long(b.end)};
}

}  // namespace occsweep
