// libFuzzer: OctoMap binary scan graphs (decodeScanGraph), with and without skipping empty nodes.
#include "fuzz_common.hpp"
#include "occsweep/data/import_graph.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto text = occsweep::fuzz::asText(data, size);
  return occsweep::fuzz::expectDataErrorOnly(
      [&] { (void)occsweep::decodeScanGraph(text, "fuzz.graph", size % 2 == 0); });
}
