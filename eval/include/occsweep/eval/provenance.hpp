// What a data set was made from, by content: the `source.provenance` hashes of its manifest
// (docs/dataset-format.md, "Provenance"), from which compare tells which data sets share a recording or a scene.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

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

}  // namespace occsweep
