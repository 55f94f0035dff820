// libFuzzer: PCD clouds, ascii and binary (decodePcd).
#include "fuzz_common.hpp"
#include "occsweep/data/import_cloud.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::size_t skipped = 0;
  return occsweep::fuzz::expectDataErrorOnly(
      [&] { (void)occsweep::decodePcd(occsweep::fuzz::asText(data, size), "fuzz.pcd", &skipped); });
}
