// Which maps and thresholds a sweep (or one shard of it) evaluates (selection.hpp).
#include <algorithm>
#include <stdexcept>

#include "occsweep/sweeps/sharding.hpp"
#include "occsweep/sweeps/selection.hpp"

namespace occsweep {

std::vector<std::uint64_t> expectedIds(const GridEnumeration& e, const SweepSelection& s) {
  if (s.group) {
    if (s.group->count == 0 || s.group->index >= s.group->count)
      throw std::invalid_argument("--group G/N needs 0 <= G < N");
    auto ids = permutationGroup(e.combinations, s.group->seed, s.group->count, s.group->index);
    std::sort(ids.begin(), ids.end());
    return ids;
  }
  std::vector<std::uint64_t> ids(e.combinations);
  for (std::uint64_t i = 0; i < e.combinations; ++i) ids[i] = i;
  return ids;
}

std::vector<SweepItem> selectWork(const GridSpec&, const GridEnumeration& e, const SweepSelection& s) {
  if (s.shard_count == 0 || s.shard_index >= s.shard_count)
    throw std::invalid_argument("--shard I/N needs 0 <= I < N");
  std::vector<SweepItem> items;
  for (std::uint64_t id : expectedIds(e, s)) {
    // The map holding this id: the last map whose first id is <= id.
    const auto it = std::upper_bound(e.first_id.begin(), e.first_id.end(), id);
    const std::uint64_t map = std::uint64_t(it - e.first_id.begin()) - 1;
    if (items.empty() || items.back().map_index != map) items.push_back({map, {}});
    items.back().thresholds.push_back(std::size_t(id - e.first_id[map]));
  }
  const Block b = contiguousBlock(items.size(), s.shard_count, s.shard_index);
  return {items.begin() + long(b.begin), items.begin() + long(b.end)};
}

}  // namespace occsweep
