// Parameter grids (Eq. 11-15, Table 1) in exact arithmetic, their canonical enumeration and stable ids.
#pragma once

#include <cstdint>
#include <filesystem>
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
  [[nodiscard]] std::vector<Fixed> values() const;
  [[nodiscard]] std::int64_t count() const;  ///< g(T) of Eq. 13, with floor: exact for any step
};

enum class GridMethod { OctoMap, Knn };

/// One grid file. Unused parameters of the other method stay empty.
struct GridSpec {
  std::string name;
  GridMethod method = GridMethod::Knn;
  std::string description;
  ParamRange p_max, p_min, p_m;       ///< both methods
  ParamRange p_h;                     ///< OctoMap
  ParamRange p_m_out, p_u, p_l;       ///< k-NN
  Fixed p_t_step = 0;                 ///< p_t runs from p_min to p_max by this step
  std::vector<int> k;                 ///< k-NN
  std::string file_hash;              ///< FNV-1a 64 of the file's bytes, hex
};

/// The parameters of one map: everything but p_t.
struct MapParams {
  Fixed p_max = 0, p_min = 0, p_m = 0, p_h = 0, p_m_out = 0, p_u = 0, p_l = 0;
  int k = 0;
};

/// The grid enumerated: maps in canonical order, each with its p_t values. A combination's id is its index in
/// the canonical order (maps in order, p_t innermost), so the ids of one map are contiguous.
struct GridEnumeration {
  std::vector<MapParams> maps;
  std::vector<std::uint64_t> first_id;          ///< id of each map's first p_t
  std::vector<std::vector<Fixed>> thresholds;   ///< p_t values of each map
  std::uint64_t combinations = 0;
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

/// Eq. 15's closed form (Eq. 13-14 with floor so it holds for steps that do not divide the range; the paper's
/// ceiling over-counts then). Must equal enumerateGrid(grid).combinations for every grid.
[[nodiscard]] std::uint64_t closedFormCount(const GridSpec& grid);

[[nodiscard]] const char* methodName(GridMethod m);

}  // namespace occsweep
