// What `results check` verifies beyond each field's type: everything a results file claims (docs/results-format.md).
#pragma once

#include <filesystem>
#include <string>

#include "occsweep/sweeps/results.hpp"

namespace occsweep {

/// Largest TP+FP+FN+TN a map can have: the voxels of OctoMap's 16-bit key space, 65536^3 = 2^48.
inline constexpr std::uint64_t kMaxRegionVoxels = std::uint64_t(1) << 48;
/// Largest grid whose Eq. 16 group membership is checked (the permutation costs 8 bytes a combination: 128 MiB).
inline constexpr std::uint64_t kMaxCheckedPermutation = std::uint64_t(1) << 24;

/// Checks without the grid file (std::runtime_error naming the file, the field and the rule): sane settings
/// (resolution, s_c, variant, statistics mode, selection within the grid's combinations), probabilities in
/// [0, 1], every map index and every id at most once, thresholds in increasing p_t, every map of the file
/// counting the same region (one TP+FP+FN+TN, one TP+FN, at most 2^48 voxels), and for a complete whole grid
/// or Eq. 16 group exactly as many ids as the selection holds (and, for a group, its ids).
void verifyClaims(const ResultsFile& f, const std::string& file);

/// With the grid enumerated (its file found, same hash): every map of the selection, cut to the shard, exactly
/// once with exactly its thresholds, and no other.
void verifyCoverage(const ResultsFile& f, const GridSpec& grid, const GridEnumeration& e, const std::string& file);

/// With the data set the file names (`results check --dataset DIR`): its content hash is the file's, and every
/// threshold counts the region's voxels at the file's resolution (TP+FP+FN+TN) and the truth's voxels (TP+FN).
void verifyAgainstDataset(const ResultsFile& f, const std::string& file, const std::filesystem::path& dataset);

}  // namespace occsweep
