// Which part of a grid one sweep (or one shard of it) evaluates: the ids a selection covers and the work items
// of a shard. Results files record the selection, merge checks the ids, the engine runs the items.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "occsweep/sweeps/grid.hpp"

namespace occsweep {

/// Which part of a grid a file covers: optionally one Eq. 16 group of ids, then one contiguous block of the
/// selected maps.
struct SweepSelection {
  struct Group {
    std::uint64_t index = 0, count = 1, seed = 0;
    friend bool operator==(const Group&, const Group&) = default;
  };
  std::optional<Group> group;
  std::uint64_t shard_index = 0, shard_count = 1;
  friend bool operator==(const SweepSelection&, const SweepSelection&) = default;
};

/// One work item: a map of the grid and the thresholds of it that the selection asks for.
struct SweepItem {
  std::uint64_t map_index = 0;
  std::vector<std::size_t> thresholds;  ///< indices into the map's p_t values (GridEnumeration::thresholdsOf)
};

/// The part of the grid a selection needs enumerated: an ungrouped shard's block of maps alone, so that a shard
/// costs the memory of its maps, not the grid's (enumerateMapRange); an Eq. 16 group's whole grid, since the
/// permutation spans every id.
[[nodiscard]] GridEnumeration enumerateSelection(const GridSpec& grid, const SweepSelection& selection);

/// The selected maps of a grid in canonical order, cut to the shard (throws for an invalid selection). `e` is the
/// whole grid or enumerateSelection's for this selection.
[[nodiscard]] std::vector<SweepItem> selectWork(const GridSpec& grid, const GridEnumeration& e,
                                                const SweepSelection& selection);

/// The ids a selection (ignoring its shard) must cover: what merge checks.
[[nodiscard]] std::vector<std::uint64_t> expectedIds(const GridEnumeration& e, const SweepSelection& selection);

}  // namespace occsweep
