// A results file of either format (docs/results-format.md): which format a path asks for, and a reader that takes a
// JSON file or a results store alike, by what the file holds rather than by its name. The formats themselves live
// apart: results.hpp (JSON) and results_store.hpp (SQLite).
#pragma once

#include <filesystem>
#include <functional>

#include "occsweep/sweeps/results.hpp"

namespace occsweep {

/// How much of each map a reader needs: everything, or its parameters, AUC and time without the thresholds'
/// counts (compare and its statistics: a store's AUCs as stored, re-derived by `results check`).
enum class MapDetail { Full, Summary };

/// Receives one map at a time, in increasing map index.
using MapVisitor = std::function<void(MapResult&&)>;

/// True when `file`'s name asks for a store: it ends in ".db" or ".sqlite" (anything else is a JSON file).
[[nodiscard]] bool isStorePath(const std::filesystem::path& file);

/// The header, completeness and seconds of a results file of either format, without its maps.
[[nodiscard]] ResultsFile readResultsHeader(const std::filesystem::path& file);
/// Every map of a results file of either format, one at a time (a JSON file is parsed whole first: small).
void forEachResultsMap(const std::filesystem::path& file, MapDetail detail, const MapVisitor& visit);
/// A results file of either format with its maps at `detail` (Summary: no thresholds; truth_voxels set).
[[nodiscard]] ResultsFile readResultsAt(const std::filesystem::path& file, MapDetail detail);

}  // namespace occsweep
