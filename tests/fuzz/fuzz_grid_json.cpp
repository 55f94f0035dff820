// libFuzzer: grid files (sweeps' parseGrid after JSON parsing, as loadGrid does). The parser's designed refusal
// is std::runtime_error naming the file; text nlohmann cannot parse never reaches it.
#include <nlohmann/json.hpp>

#include "fuzz_common.hpp"
#include "occsweep/sweeps/grid.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(occsweep::fuzz::asText(data, size));
  } catch (const nlohmann::json::exception&) {  // not JSON (parse_error, or out_of_range for 1e999)
    return 0;
  }
  try {
    (void)occsweep::parseGrid(j, "fuzz.json");
  } catch (const std::runtime_error&) {
  }
  return 0;
}
