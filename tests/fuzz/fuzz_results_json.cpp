// libFuzzer: results files (sweeps' parseResults after JSON parsing, as readResults does). The designed refusal
// is std::runtime_error naming the file and field.
#include "fuzz_common.hpp"
#include "occsweep/sweeps/results.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return occsweep::fuzz::expectRuntimeErrorOnlyAfterJson(
      data, size, [](const nlohmann::json& j) { (void)occsweep::parseResults(j, "fuzz.json"); });
}
