// Every JSON input of occsweep (manifests, results, plans, grids): bounded by size before it is parsed, and a key
// given twice in one object refused.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace occsweep {

/// The whole file parsed as JSON: readJsonBytes' refusals, then a DataError "FILE: not valid JSON: ..." when it is
/// not (a syntax error, a truncated file, a number like 1e999 that no double holds), or gives a key twice in one
/// object. One home for every JSON input: manifests, results, plans.
[[nodiscard]] nlohmann::json readJsonFile(const std::filesystem::path& file);
/// The bytes of a JSON input (readJsonFile, a grid): readFileBytes' refusals, and a LimitError naming the file and
/// --max-json-bytes for one past limits().json_bytes, before a byte is read.
[[nodiscard]] std::string readJsonBytes(const std::filesystem::path& file);

/// `text` (the bytes of `file`) parsed as JSON, with readJsonFile's error.
[[nodiscard]] nlohmann::json parseJsonText(std::string_view text, const std::filesystem::path& file);
/// parseJsonText, and a key given twice in one object is refused (DataError naming the file and the key's path):
/// JSON parsers keep only the last, so a hand-written file (a grid) would silently lose the first.
[[nodiscard]] nlohmann::json parseJsonTextUniqueKeys(std::string_view text, const std::filesystem::path& file);
}  // namespace occsweep
