// Ranked point cloud sets for plans made before the data exist (`occsweep cluster select`).
#pragma once

#include <filesystem>
#include <vector>

namespace occsweep {

/// Reads the ranking.json of every generation block of one data set, ranks all their sets together (naive FDR
/// ascending, NaN last, then TPR descending, then id: the generator's order) and writes OUT/ with links
/// pcs-NNNN and rank-N (1 = best) to the set folders, and OUT/sets.json. OUT is built under a temporary name and
/// renamed. Returns the number of sets; std::runtime_error naming the file for a bad ranking or a missing folder.
std::size_t selectRanked(const std::vector<std::filesystem::path>& rankings, const std::filesystem::path& out);

}  // namespace occsweep
