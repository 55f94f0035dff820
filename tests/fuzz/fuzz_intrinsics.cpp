// libFuzzer: intrinsics files, a 3x3 camera matrix as text or a cam_params.json object (decodeIntrinsics).
#include "fuzz_common.hpp"
#include "occsweep/data/import_intrinsics.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return occsweep::fuzz::expectDataErrorOnly(
      [&] { (void)occsweep::decodeIntrinsics(occsweep::fuzz::asText(data, size), "fuzz-intrinsics", false); });
}
