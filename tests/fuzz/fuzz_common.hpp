// Shared by the libFuzzer targets: run a reader on the input; a DataError (the designed refusal) is fine, any other
// exception, crash, sanitizer report, leak, hang or huge allocation is a finding.
#pragma once

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string_view>

#include <nlohmann/json.hpp>

#include "occsweep/io/data_error.hpp"
#include "occsweep/methods/builtin_methods.hpp"

namespace occsweep::fuzz {

/// The grid and results parsers look methods up: registered before the first input, as the command does.
inline const bool kBuiltinMethodsRegistered = (registerBuiltinMethods(), true);

inline std::string_view asText(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

template <class Reader>
int expectDataErrorOnly(Reader&& read) {
  try {
    read();
  } catch (const DataError&) {
  }
  return 0;
}

/// The sweeps' JSON files (grid, results): text nlohmann cannot parse never reaches the parser (parse_error, or
/// out_of_range for 1e999), as in loadGrid/readResults; the parser's designed refusal is std::runtime_error.
template <class Parser>
int expectRuntimeErrorOnlyAfterJson(const std::uint8_t* data, std::size_t size, Parser&& parse) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(asText(data, size));
  } catch (const nlohmann::json::exception&) {
    return 0;
  }
  try {
    parse(j);
  } catch (const std::runtime_error&) {
  }
  return 0;
}

}  // namespace occsweep::fuzz
