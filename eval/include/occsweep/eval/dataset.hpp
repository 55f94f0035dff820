// A data set: scans, ground truth and evaluation region, and its on-disk form (docs/dataset-format.md).
#pragma once

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "occsweep/core/point_cloud_set.hpp"
#include "occsweep/eval/ground_truth.hpp"

namespace occsweep {

struct ReplaceableOutput;  // occsweep/io/output_target.hpp

struct Dataset {
  std::string name;
  PointCloudSet scans;
  TruthSources truth;
  AxisBox region;
  nlohmann::json source = nlohmann::json::object();  ///< how it was made (generator and its settings)
};

/// Axis-aligned bounding box of every point and every origin of `scans` (which must not be empty).
[[nodiscard]] AxisBox boundingBox(const PointCloudSet& scans);

/// Writes DIR/manifest.json and DIR/scans/NNNNNN.f32 (+ truth files). Built in a temporary folder beside DIR
/// and renamed into place (OutputFolder), so a killed write never leaves a half data set. Replaces an existing DIR:
/// callers check it first with checkOutputTarget(dir, force, datasetOutput()).
void writeDataset(const Dataset& dataset, const std::filesystem::path& dir);

/// A data-set folder as writeDataset writes it (manifest with the data-set format, nothing else): what --force
/// may replace.
[[nodiscard]] ReplaceableOutput datasetOutput();

/// Reads and checks a data set. Throws DataError naming the file and field: missing or truncated files,
/// NaN or infinite coordinates, empty scans, bad manifest fields.
/// Scans' point counts are summed from the manifest and checked against limits().points before any is read.
[[nodiscard]] Dataset readDataset(const std::filesystem::path& dir);

/// makeGroundTruth of a data set read from `dir`; a region it refuses (past limits().region_voxels, no voxel centre
/// at this resolution, min > max) is a DataError naming DIR/manifest.json (and the field `region`).
[[nodiscard]] GroundTruth groundTruthOf(const Dataset& dataset, const std::filesystem::path& dir, double resolution);

/// FNV-1a 64 over the manifest and every binary file in manifest order, as 16 hex digits: the data set's
/// content hash recorded in results (docs/definitions.md, Results files).
[[nodiscard]] std::string datasetContentHash(const std::filesystem::path& dir);

}  // namespace occsweep
