// libFuzzer: plain `x y z` text clouds (decodeXyz).
#include "fuzz_common.hpp"
#include "occsweep/data/import_cloud.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return occsweep::fuzz::expectDataErrorOnly([&] { (void)occsweep::decodeXyz(occsweep::fuzz::asText(data, size), "fuzz.xyz"); });
}
