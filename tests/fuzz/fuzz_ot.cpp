// libFuzzer: OctoMap .ot maps as `occsweep mapdiff` reads them (decodeOcTree), then expanded as mapdiff
// does: the voxel limit must keep expand() bounded too (-malloc_limit_mb catches a count the walk trusted).
#include "fuzz_common.hpp"
#include "occsweep/core/limits.hpp"
#include "occsweep/data/octree_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  occsweep::limits().map_voxels = 1 << 16;  // a small limit: each run stays fast; the bound is what is fuzzed
  return occsweep::fuzz::expectDataErrorOnly([&] {
    auto tree = occsweep::decodeOcTree(occsweep::fuzz::asText(data, size), "fuzz.ot");
    tree->expand();
  });
}
