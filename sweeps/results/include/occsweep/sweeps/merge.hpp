// Merging the shards of one sweep (the comparison of methods is compare.hpp).
#pragma once

#include <filesystem>
#include <vector>

#include "occsweep/sweeps/results.hpp"

namespace occsweep {

/// Merges the shards of one sweep. Refuses (std::runtime_error naming the file) an incomplete file, a file of
/// another grid, data set, group or map setting, a duplicated combination, a combination outside the selection
/// and a missing one. When the grid file is found and its hash matches, every id's parameters are checked too.
/// Inputs of either format (results_store.hpp) are read map by map.
[[nodiscard]] ResultsFile mergeResults(const std::vector<std::filesystem::path>& files);
/// The same written to `out` atomically in the format its name asks for; into a store, map by map (memory: a bit
/// per combination of the grid and the grid's enumeration, not the results). Returns the number of maps.
std::uint64_t mergeResultsInto(const std::vector<std::filesystem::path>& files, const std::filesystem::path& out);

/// The ids a results file covers, checked against its selection by the caller.
[[nodiscard]] std::vector<std::uint64_t> coveredIds(const ResultsFile& f);

/// Checks one file's ids and parameters against its grid, when the grid file is found (returns false if not).
bool checkAgainstGrid(const ResultsFile& f, const std::string& file);

}  // namespace occsweep
