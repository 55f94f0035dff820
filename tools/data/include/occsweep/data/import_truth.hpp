// Ground truth of a real recording (docs/import.md): a PLY mesh, a PLY or PCD point cloud, or a JSON list of boxes.
#pragma once

#include <array>
#include <filesystem>
#include <string_view>

#include "occsweep/eval/ground_truth.hpp"

namespace occsweep {

/// By extension: .ply with faces -> mesh, .ply without faces or .pcd -> points, .json -> boxes, given either as
/// `[{"min": [x,y,z], "max": [x,y,z]}, ...]` or as `{"boxes": [...]}`. DataError for anything malformed, NaN or
/// infinite values, min > max, or a source with nothing in it.
/// `shift` (a data set's --shift) is added to every coordinate in double, before the one rounding of a point or
/// vertex to float32, as the scan readers do (docs/import.md, "Far-away (georeferenced) clouds").
[[nodiscard]] TruthSources decodeTruth(std::string_view bytes, const std::filesystem::path& file,
                                       const std::array<double, 3>& shift = {0, 0, 0});
[[nodiscard]] TruthSources readTruth(const std::filesystem::path& file, const std::array<double, 3>& shift = {0, 0, 0});

/// Margin around the truth's bounding box of the default evaluation region, metres (docs/robustness.md).
inline constexpr double kTruthRegionMargin = 0.5;

/// The default evaluation region of a data set with truth: the bounding box of every box, triangle and point of
/// the truth grown by kTruthRegionMargin on every side, so that a few far points of a real cloud (disparity near
/// zero) do not make the region huge.
[[nodiscard]] AxisBox truthRegion(const TruthSources& truth);

/// Boxes from JSON text (the fuzzable part of decodeTruth).
[[nodiscard]] std::vector<AxisBox> decodeTruthBoxes(std::string_view text, const std::filesystem::path& file);

}  // namespace occsweep
