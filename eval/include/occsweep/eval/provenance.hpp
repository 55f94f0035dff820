// What a data set was made from, by content: the `source.provenance` hashes of its manifest
// (docs/dataset-format.md, "Provenance"), from which compare tells which data sets share a recording or a scene.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "occsweep/core/point_cloud_set.hpp"
#include "occsweep/eval/ground_truth.hpp"
#include "occsweep/io/fnv1a.hpp"

namespace occsweep {

/// FNV-1a 64 of bytes in memory, as 16 hex digits (decoded images, a scene's description as JSON text).
[[nodiscard]] inline std::string contentHash(std::string_view bytes) {
  Fnv1a h;
  h.feed(bytes);
  return h.hex();
}

/// FNV-1a 64 of each file's bytes, in order, as a JSON array of hex strings; DataError when one cannot be read.
[[nodiscard]] inline nlohmann::json fileContentHashes(const std::vector<std::filesystem::path>& files) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& file : files) {
    Fnv1a h;
    h.feedFile(file);
    out.push_back(h.hex());
  }
  return out;
}

/// Sets `truth` (one hash of the truth as stored: every box bound, triangle and point coordinate) and `region` (of
/// `[[min], [max]]` as JSON text) in `provenance`: values, not file bytes, so one truth written with other comments,
/// line ends or formats is still one scene.
void recordTruthAndRegion(nlohmann::json& provenance, const TruthSources& truth, const AxisBox& region);

/// Sets `points` in `provenance`: one hash of every scan's origin and point coordinates as read, so that one recording
/// whose files were re-encoded or re-written (another image format, other line ends, a byte appended that the reader
/// skips) is still one recording.
void recordPoints(nlohmann::json& provenance, const PointCloudSet& scans);

/// DataError naming `file` and `field` unless `provenance` is an object of the documented fields only, each a hash
/// of 16 lowercase hex digits (`inputs`, `poses`, `truth`: arrays of them): a hand-edited one would change the units.
void checkProvenance(const nlohmann::json& provenance, const std::filesystem::path& file, const std::string& field);

}  // namespace occsweep
