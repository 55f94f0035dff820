// What a generated data set records: the `source` of every point cloud set, ranking.json and timing.json.
#pragma once

#include <filesystem>
#include <vector>

#include <nlohmann/json.hpp>

#include "occsweep/io/output_file.hpp"

#include "generate.hpp"

namespace occsweep::stereo {

/// Everything needed to repeat one point cloud set: generator, scale, camera, orbit, render and SGBM settings,
/// the point cloud parameter id and the grid's hash. No timings, so equal inputs give equal bytes.
[[nodiscard]] nlohmann::json sourceJson(const DatasetName& name, const GenerateConfig& config,
                                        const StereoCamera& camera, const PointCloudGrid& grid, std::int64_t id,
                                        const SgbmParams& params);

/// Sorts by naive FDR ascending (NaN last), then TPR descending, then id ascending, and numbers the ranks 1..n.
void rankSets(std::vector<PointCloudSetSummary>& sets);

/// ranking.json and timing.json of occsweep's, proven by their own "format" fields.
[[nodiscard]] ReplaceableOutput rankingOutput();
[[nodiscard]] ReplaceableOutput timingOutput();

/// DIR/ranking.json (deterministic) and DIR/timing.json, each written to a temporary name and renamed.
void writeRanking(const DatasetSummary& summary, const GenerateConfig& config, const PointCloudGrid& grid,
                  const std::filesystem::path& dir);

/// The summary row of one data set, for OUT/summary.json and docs/datasets.md.
[[nodiscard]] nlohmann::json summaryRow(const DatasetSummary& summary);

}  // namespace occsweep::stereo
