// libFuzzer: PGM depth images, P5 and P2 (decodePgm).
#include "fuzz_common.hpp"
#include "occsweep/data/import_depth.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return occsweep::fuzz::expectDataErrorOnly([&] { (void)occsweep::decodePgm(occsweep::fuzz::asText(data, size), "fuzz.pgm"); });
}
