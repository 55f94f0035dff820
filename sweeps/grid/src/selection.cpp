// Which maps and thresholds a sweep (or one shard of it) evaluates (selection.hpp).
#include <algorithm>
#include <stdexcept>
#include <string>

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

namespace {

void checkShard(const SweepSelection& s) {
  if (s.shard_count == 0 || s.shard_index >= s.shard_count)
    throw std::invalid_argument("--shard I/N needs 0 <= I < N");
}

}  // namespace

GridEnumeration enumerateSelection(const GridSpec& grid, const SweepSelection& s) {
  checkShard(s);
  if (s.group) return enumerateGrid(grid);  // Eq. 16 permutes every id of the grid
  const Block b = contiguousBlock(thresholdedMapCount(grid), s.shard_count, s.shard_index);
  return enumerateMapRange(grid, b.begin, b.end);
}

std::vector<SweepItem> selectWork(const GridSpec& grid, const GridEnumeration& e, const SweepSelection& s) {
  checkShard(s);
  std::vector<SweepItem> items;
  if (s.group) {
    if (e.first_map != 0 || e.maps.size() != e.map_count)
      throw std::logic_error("grid " + grid.name + ": an Eq. 16 group needs the whole grid enumerated");
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
  // Ungrouped: the shard's block of the maps with p_t, each with every p_t, from the maps the enumeration holds.
  const Block b = contiguousBlock(e.thresholded_maps, s.shard_count, s.shard_index);
  std::uint64_t ordinal = e.thresholded_before;
  for (std::size_t i = 0; i < e.maps.size(); ++i) {
    if (e.thresholds[i].empty()) continue;
    if (ordinal >= b.begin && ordinal < b.end) {
      SweepItem& item = items.emplace_back(SweepItem{e.first_map + i, {}});
      for (std::size_t t = 0; t < e.thresholds[i].size(); ++t) item.thresholds.push_back(t);
    }
    ++ordinal;
  }
  if (items.size() != b.end - b.begin)
    throw std::logic_error("grid " + grid.name + ": the enumeration does not hold shard " +
                           std::to_string(s.shard_index) + "/" + std::to_string(s.shard_count));
  return items;
}

}  // namespace occsweep
