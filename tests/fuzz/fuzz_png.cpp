// libFuzzer: 16/8-bit greyscale PNG depth images through libpng (decodePng).
#include "fuzz_common.hpp"
#include "occsweep/data/import_depth.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return occsweep::fuzz::expectDataErrorOnly([&] { (void)occsweep::decodePng(occsweep::fuzz::asText(data, size), "fuzz.png"); });
}
