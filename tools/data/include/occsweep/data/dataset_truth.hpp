// Ground truth of a data set read from a folder: eval's makeGroundTruth, with its refusals naming the manifest.
#pragma once

#include <filesystem>

#include "occsweep/data/dataset.hpp"
#include "occsweep/eval/ground_truth.hpp"

namespace occsweep {

/// makeGroundTruth(d.truth, d.region, resolution); a region it refuses (no voxel centre at this resolution,
/// min > max) is a DataError naming DIR/manifest.json and the field `region`.
[[nodiscard]] GroundTruth datasetGroundTruth(const Dataset& d, const std::filesystem::path& dir, double resolution);

}  // namespace occsweep
