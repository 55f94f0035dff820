// libFuzzer: ground-truth boxes as JSON (decodeTruthBoxes).
#include "fuzz_common.hpp"
#include "occsweep/data/import_truth.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return occsweep::fuzz::expectDataErrorOnly(
      [&] { (void)occsweep::decodeTruthBoxes(occsweep::fuzz::asText(data, size), "fuzz.json"); });
}
