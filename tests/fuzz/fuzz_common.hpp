// Shared by the libFuzzer targets: run a reader on the input; a DataError (the designed refusal) is fine, any other
// exception, crash, sanitizer report, leak, hang or huge allocation is a finding.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "occsweep/data/data_error.hpp"

namespace occsweep::fuzz {

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

}  // namespace occsweep::fuzz
