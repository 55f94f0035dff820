// Coordinates a data set may hold and a map can index (docs/robustness.md, "Numbers that must not be wrong"):
// finite float32 values, since a data set stores float32; inside OctoMap's 16-bit key range at the map's
// resolution, since liboctomap and the k-NN mapper silently drop a point outside it.
#pragma once

#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "dataset.hpp"

namespace occsweep {

/// Throws DataError(file, where, ...) when a point is not a finite float32 (an input value beyond 3.4e38 becomes
/// infinite when stored). `hint` names what may have caused it (flags, the pose), appended to the message.
void requireFinitePoints(const std::vector<octomap::point3d>& points, const std::string& file, const std::string& where,
                         const std::string& hint = "");
/// The same for a scan's points and its origin.
void requireFiniteScan(const Scan& scan, const std::string& file, const std::string& where,
                       const std::string& hint = "");

/// OctoMap's key range on every axis at `resolution`: [lowest, highest). A coordinate c has a key when
/// floor(c / resolution) lies in [-32768, 32767] (liboctomap's coordToKeyChecked with 16-bit keys).
struct KeyRange {
  double resolution = 0.1, lowest = 0.0, highest = 0.0;
  [[nodiscard]] bool holds(double coordinate) const;
  [[nodiscard]] std::string text() const;  ///< "[-3276.8, 3276.8) m at resolution 0.1 m"
};
[[nodiscard]] KeyRange keyRange(double resolution);

/// Throws DataError naming DIR/manifest.json, the field and the value when a scan point or origin, a truth box,
/// mesh vertex or point, or the region lies outside the key range at `resolution`. For scans the message gives
/// the `import ... --shift X Y Z` that centres the scans on the origin.
void requireInKeyRange(const Dataset& dataset, const std::filesystem::path& dir, double resolution);

/// The shift that moves the centre of the scans' bounding box to the origin, in whole metres, on each axis where
/// the scans leave `range` (0 on the others).
[[nodiscard]] std::array<double, 3> centringShift(const PointCloudSet& scans, const KeyRange& range);
/// The same from the scans' bounding box (boundingBox).
[[nodiscard]] std::array<double, 3> centringShift(const AxisBox& box, const KeyRange& range);

/// Adds `shift` to every point, origin, truth source and the region, and records it as source.shift (added to
/// an earlier shift). Throws std::invalid_argument naming --shift when a shifted coordinate overflows float32.
void applyShift(Dataset& dataset, const std::array<double, 3>& shift);

/// Records `shift` as source.shift (added to an earlier shift) for scans that their reader already placed with it
/// (import cloud rounds pose + shift to float32 once, docs/import.md); applyShift ends with it.
void recordShift(Dataset& dataset, const std::array<double, 3>& shift);

/// A data set's recorded shift (source.shift), zero when there is none.
[[nodiscard]] std::array<double, 3> recordedShift(const Dataset& dataset);

/// Truth read in the recording's frame, moved by `shift` (so it lines up with a shifted data set).
void shiftTruth(TruthSources& truth, const std::array<double, 3>& shift, const std::string& file);

}  // namespace occsweep
