// libFuzzer: results files (sweeps' parseResults after JSON parsing, as readResults does). The designed refusal
// is std::runtime_error naming the file and field; text nlohmann cannot parse never reaches it.
#include <nlohmann/json.hpp>

#include "fuzz_common.hpp"
#include "occsweep/sweeps/results.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(occsweep::fuzz::asText(data, size));
  } catch (const nlohmann::json::exception&) {  // not JSON (parse_error, or out_of_range for 1e999)
    return 0;
  }
  try {
    (void)occsweep::parseResults(j, "fuzz.json");
  } catch (const std::runtime_error&) {
  }
  return 0;
}
