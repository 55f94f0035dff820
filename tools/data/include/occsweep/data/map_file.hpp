// A map as `occsweep map` writes it (docs/methods.md, "One map"): OctoMap's .ot, which keeps the
// resolution and the log-odds only, and beside it MAP.ot.json with what built it (method, every parameter, the
// settings, the data set's hash). Both are written, or neither.
#pragma once

#include <filesystem>

#include <nlohmann/json.hpp>
#include <octomap/OcTree.h>

#include "occsweep/io/output_file.hpp"

namespace occsweep {

/// The "format" of MAP.ot.json.
inline constexpr const char* kMapSettingsFormat = "occsweep-map-settings";

/// Whether `file` is a MAP.ot.json occsweep wrote (its format field, or, from before the field, its keys).
[[nodiscard]] bool isMapSettingsFile(const std::filesystem::path& file);

/// A .ot is occsweep's own when it is an OctoMap .ot with occsweep's settings beside it (a .ot from another tool
/// has no .ot.json, and is refused even with --force).
[[nodiscard]] ReplaceableOutput mapOutput();

/// Refuses (OutputError, std::invalid_argument) an `out` that is not a .ot name or whose .ot or .ot.json stands
/// and may not be replaced (with `force`, only occsweep's own). Settings left without their map (a kill between the
/// two renames) are occsweep's leftover and replaced.
void checkMapTarget(const std::filesystem::path& out, bool force);

/// The map and its settings, both written out and checked before either is renamed: a failed write (a full disk,
/// `ulimit -f`) or a file put at either name meanwhile leaves neither.
void writeMapFile(const octomap::OcTree& tree, const nlohmann::json& settings, const std::filesystem::path& out);

}  // namespace occsweep
