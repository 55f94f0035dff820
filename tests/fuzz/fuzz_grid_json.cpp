// libFuzzer: grid files (sweeps' parseGrid after JSON parsing, as loadGrid does). The parser's designed refusal
// is std::runtime_error naming the file.
#include "fuzz_common.hpp"
#include "occsweep/sweeps/grid.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return occsweep::fuzz::expectRuntimeErrorOnlyAfterJson(
      data, size, [](const nlohmann::json& j) { (void)occsweep::parseGrid(j, "fuzz.json"); });
}
