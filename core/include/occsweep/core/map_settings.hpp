// The settings every map of a sweep shares, whatever its method: the voxel edge, the range s_c, Algorithm 1's update
// variant and where Eq. 8's mu and sigma come from. One value type, carried unchanged from the command through the
// sweep's configuration, the results header (its "map" object, docs/results-format.md) and the engines to the
// method (MapContext).
#pragma once

#include <array>
#include <cmath>
#include <optional>
#include <string>
#include <string_view>

#include "decimal_text.hpp"
#include "enum_names.hpp"

namespace occsweep {

/// Algorithm 1 word for word (Literal) or with OctoMap's "occupied wins" (Default); see voxel_update_rule.hpp.
enum class UpdateVariant { Default, Literal };

/// Where mu and sigma of Eq. 8 come from: the whole point cloud set in a first pass (Batch, the paper's),
/// or the running Welford values after the current scan (Online, for a robot mapping as it goes).
enum class StatsMode { Batch, Online };

/// The names of both enums in results files (map.variant, map.stats: docs/results-format.md), in the .ot.json of
/// `occsweep map` and on the command line (--variant, --stats; .list() for CLI11's IsMember).
inline constexpr EnumNames<UpdateVariant, 2> kUpdateVariantNames{
    "variant", {{{UpdateVariant::Default, "default"}, {UpdateVariant::Literal, "literal"}}}};
inline constexpr EnumNames<StatsMode, 2> kStatsModeNames{
    "stats", {{{StatsMode::Batch, "batch"}, {StatsMode::Online, "online"}}}};

/// "default" or "literal".
[[nodiscard]] inline const char* toText(UpdateVariant variant) { return kUpdateVariantNames.text(variant); }
/// "batch" or "online".
[[nodiscard]] inline const char* toText(StatsMode stats) { return kStatsModeNames.text(stats); }

/// The variant of that name; throws std::invalid_argument naming it and the accepted names.
[[nodiscard]] inline UpdateVariant parseUpdateVariant(std::string_view name) { return kUpdateVariantNames.parse(name); }
/// The statistics mode of that name; throws std::invalid_argument naming it and the accepted names.
[[nodiscard]] inline StatsMode parseStatsMode(std::string_view name) { return kStatsModeNames.parse(name); }

/// What every map of a sweep shares. The defaults are the paper's (Section 4.2).
struct MapSettings {
  double resolution = 0.1;  ///< voxel edge in metres
  double s_c = 4.0;         ///< maximum range in metres: splits z_in from z_out; longer rays are cut, free space only
  UpdateVariant variant = UpdateVariant::Default;  ///< how a scan's hits and misses of one voxel combine (k-NN)
  StatsMode stats = StatsMode::Batch;              ///< mu and sigma of Eq. 8 (k-NN)
  friend bool operator==(const MapSettings&, const MapSettings&) = default;
};

/// The settings' names, as results files, plans and `map`'s MAP.ot.json key them ("map" object), and as no method's
/// parameter may be named.
inline constexpr std::array<const char*, 4> kMapSettingNames = {"resolution", "s_c", "variant", "stats"};

/// The rule both lengths (resolution, s_c) obey, and its words.
[[nodiscard]] inline bool admitsLength(double metres) { return std::isfinite(metres) && metres > 0.0; }
inline constexpr const char* kLengthRule = "must be a finite number > 0 (metres)";

/// The first setting out of range, as a sentence naming it; none if both lengths obey admitsLength.
[[nodiscard]] std::optional<std::string> brokenSetting(const MapSettings& settings);

// ---------------------------------------------------------------------------------------------------------

inline std::optional<std::string> brokenSetting(const MapSettings& settings) {
  if (!admitsLength(settings.resolution))
    return std::string("resolution ") + kLengthRule + " (resolution = " + detail::fmt(settings.resolution) + ")";
  if (!admitsLength(settings.s_c))
    return std::string("s_c ") + kLengthRule + " (s_c = " + detail::fmt(settings.s_c) + ")";
  return std::nullopt;
}

}  // namespace occsweep
