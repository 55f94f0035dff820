// The flags of the settings every map shares (--resolution, --s-c, --variant, --stats): one spelling and one help
// text for `sweep`, `map` and `cluster plan --sweep-args`, read into one MapSettings (docs/cli.md, "Flags").
#pragma once

#include <map>
#include <string>

#include <CLI/CLI.hpp>

#include "occsweep/core/map_settings.hpp"
#include "option_checks.hpp"

namespace occsweep::cli {

/// The settings as the flags hold them: the lengths as numbers, the variant and statistics mode by name; the defaults
/// are MapSettings'.
struct MapSettingFlags {
  double resolution = MapSettings{}.resolution, s_c = MapSettings{}.s_c;
  std::string variant = toText(MapSettings{}.variant), stats = toText(MapSettings{}.stats);
  /// The settings the flags give (the names were checked by the flags).
  [[nodiscard]] MapSettings settings() const {
    return {resolution, s_c, parseUpdateVariant(variant), parseStatsMode(stats)};
  }
};

/// Adds the four flags to `app`, bound to `flags`; each option by its flag name, for a command that must know which
/// were given.
inline std::map<std::string, CLI::Option*> addMapSettingFlags(CLI::App& app, MapSettingFlags& flags) {
  return {{"--resolution", app.add_option("--resolution", flags.resolution, "Voxel edge, metres")
                               ->capture_default_str()
                               ->check(numberAbove(0))},
          {"--s-c", app.add_option("--s-c", flags.s_c, "Maximum range s_c, metres")
                        ->capture_default_str()
                        ->check(numberAbove(0))},
          {"--variant", app.add_option("--variant", flags.variant,
                                       "k-NN update: default (occupied wins) or literal (Algorithm 1 word for word)")
                            ->check(CLI::IsMember(kUpdateVariantNames.list()))
                            ->capture_default_str()},
          {"--stats", app.add_option("--stats", flags.stats, "k-NN mu, sigma: batch (whole set, the paper's) or online")
                          ->check(CLI::IsMember(kStatsModeNames.list()))
                          ->capture_default_str()}};
}

}  // namespace occsweep::cli
