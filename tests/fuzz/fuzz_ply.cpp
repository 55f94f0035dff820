// libFuzzer: PLY clouds and meshes, ascii and binary of both endians (decodePly).
#include "fuzz_common.hpp"
#include "occsweep/data/import_cloud.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return occsweep::fuzz::expectDataErrorOnly([&] { (void)occsweep::decodePly(occsweep::fuzz::asText(data, size), "fuzz.ply"); });
}
