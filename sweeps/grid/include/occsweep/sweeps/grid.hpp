// Parameter grids (Eq. 11-15, Table 1) in exact arithmetic, their canonical enumeration and stable ids.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace occsweep {

/// An exact decimal: value = units / kFixedScale. 0.98 is 980000, never 0.97999999.
using Fixed = std::int64_t;
inline constexpr Fixed kFixedScale = 1'000'000;
[[nodiscard]] inline double toDouble(Fixed v) { return double(v) / double(kFixedScale); }

/// A parameter's values: min + i*step for i = 0, 1, ... while <= max (docs/definitions.md, Parameter grids).
/// A fixed value has min == max.
struct ParamRange {
  Fixed min = 0, max = 0, step = 0;
  std::vector<Fixed> listed;  ///< an integer parameter's values as listed (k: [1, 3]); then min, max, step unused
  [[nodiscard]] std::vector<Fixed> values() const;
  [[nodiscard]] std::int64_t count() const;  ///< g(T) of Eq. 13, with floor: exact for any step
};

/// What results need of a method's parameters (every one but p_t): their names in the method's order
/// (MappingMethod::parameters) and which are integers (written as JSON integers, as k).
struct ParameterLayout {
  std::vector<std::string> names;
  std::vector<bool> integer;
  /// The index of `name`; std::invalid_argument naming it when the layout has none.
  [[nodiscard]] std::size_t index(const std::string& name) const;
  [[nodiscard]] bool has(const std::string& name) const;
  friend bool operator==(const ParameterLayout&, const ParameterLayout&) = default;
};

/// One grid file: a registered method (docs/methods.md) and a range of values for each of its parameters.
struct GridSpec {
  std::string name;
  std::string method;                 ///< a registered method's name (method_registry.hpp)
  std::string description;
  ParameterLayout layout;             ///< the method's parameters
  std::vector<ParamRange> ranges;     ///< per parameter of `layout`; integer parameters list their values
  Fixed p_t_step = 0;                 ///< p_t runs from p_min to p_max by this step
  std::string file_hash;              ///< FNV-1a 64 of the file's bytes, hex
  /// The range of parameter `name`.
  [[nodiscard]] const ParamRange& range(const std::string& name) const { return ranges.at(layout.index(name)); }
};

/// The parameters of one map: every parameter of its method but p_t, in the order of its ParameterLayout.
struct MapParams {
  std::vector<Fixed> values;
  friend bool operator==(const MapParams&, const MapParams&) = default;
};

/// The value of parameter `name` of a map.
[[nodiscard]] Fixed parameter(const ParameterLayout& layout, const MapParams& params, const std::string& name);
/// The same as a double.
[[nodiscard]] inline double parameterValue(const ParameterLayout& layout, const MapParams& params,
                                           const std::string& name) {
  return toDouble(parameter(layout, params, name));
}

/// The grid enumerated, whole or a window of it: maps in canonical order, each with its p_t values. A
/// combination's id is its index in the canonical order (maps in order, p_t innermost), so the ids of one map are
/// contiguous. A window (enumerateMapRange) holds the maps first_map, first_map + 1, ... only; the counts are always
/// the whole grid's.
struct GridEnumeration {
  std::vector<MapParams> maps;
  std::vector<std::uint64_t> first_id;          ///< id of each map's first p_t
  std::vector<std::vector<Fixed>> thresholds;   ///< p_t values of each map
  std::uint64_t combinations = 0;               ///< of the whole grid
  std::uint64_t first_map = 0;                  ///< the map index of maps[0]
  std::uint64_t map_count = 0;                  ///< maps of the whole grid
  /// Maps of the whole grid with at least one p_t (a shard is a block of these), and how many come before maps[0].
  std::uint64_t thresholded_maps = 0, thresholded_before = 0;

  [[nodiscard]] bool holds(std::uint64_t map_index) const {
    return map_index >= first_map && map_index - first_map < maps.size();
  }
  /// The parameters, first id and p_t values of a map it holds (std::out_of_range otherwise).
  [[nodiscard]] const MapParams& map(std::uint64_t map_index) const { return maps.at(position(map_index)); }
  [[nodiscard]] std::uint64_t firstId(std::uint64_t map_index) const { return first_id.at(position(map_index)); }
  [[nodiscard]] const std::vector<Fixed>& thresholdsOf(std::uint64_t map_index) const {
    return thresholds.at(position(map_index));
  }

 private:
  [[nodiscard]] std::size_t position(std::uint64_t map_index) const {
    return map_index < first_map ? maps.size() : std::size_t(map_index - first_map);
  }
};

/// Reads and checks a grid file. Throws std::runtime_error naming the file, the key and the rule: unknown keys,
/// step <= 0 on a range, min > max, values outside Eq. 12's bounds, more than 6 decimals.
[[nodiscard]] GridSpec parseGrid(const nlohmann::json& j, const std::string& file);
[[nodiscard]] GridSpec loadGrid(const std::filesystem::path& file);
/// A grid by path, or by name: NAME.json in $OCCSWEEP_GRIDS, then in each folder given to addGridFolder, in that
/// order (docs/install.md, "Where the command finds its grids"). Throws std::runtime_error naming every folder tried.
[[nodiscard]] std::filesystem::path resolveGridPath(const std::string& name_or_path);
/// Adds a folder that resolveGridPath searches for grids by name. The library knows no folder of its own: the
/// command adds its installed grids (share/occsweep/grids beside its own folder), a test or a downstream program
/// the folder it ships. Call before any sweep starts (the list is not guarded for concurrent changes).
void addGridFolder(const std::filesystem::path& folder);

[[nodiscard]] GridEnumeration enumerateGrid(const GridSpec& grid);
/// The window of the grid holding its thresholded maps (those with at least one p_t) [begin, end), and any map
/// without p_t between them: memory by the window, checked against the combinations limit for the window's
/// combinations; time of two walks over the grid's maps (counting the window's combinations, then storing its maps),
/// none stored but the window's (docs/grids.md, "Sweep shards").
[[nodiscard]] GridEnumeration enumerateMapRange(const GridSpec& grid, std::uint64_t begin, std::uint64_t end);
/// The grid's maps with at least one p_t: by the closed form where there is one (closedFormCount), else counted
/// map by map without storing them.
[[nodiscard]] std::uint64_t thresholdedMapCount(const GridSpec& grid);

/// Where counts of combinations saturate: a count at this value means "at least this many".
inline constexpr std::uint64_t kCountCeiling = 1ULL << 62;

/// Eq. 15's closed form (Eq. 13-14 with floor so it holds for steps that do not divide the range; the paper's
/// ceiling over-counts then) for any method whose relations form a forest; none otherwise. Must equal
/// enumerateGrid(grid).combinations for every grid it has, up to kCountCeiling. Memory: the parameters' values
/// (each range bounded by the combinations limit); time: the pairs of p_max and p_min values (at most 10^8).
[[nodiscard]] std::optional<std::uint64_t> closedFormCount(const GridSpec& grid);

/// The grid's combinations without enumerating them: Eq. 15 where it holds, else a count over the maps.
[[nodiscard]] std::uint64_t combinationCount(const GridSpec& grid);

/// The layout of a registered method's parameters.
[[nodiscard]] ParameterLayout layoutOf(const std::string& method);

}  // namespace occsweep
