// libFuzzer: pose files; the first byte's low bit picks quaternion lines or 4x4 matrices (decodePoses).
#include "fuzz_common.hpp"
#include "occsweep/data/import_pose.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const auto format = data[0] & 1 ? occsweep::PoseFormat::Matrix : occsweep::PoseFormat::Quaternion;
  return occsweep::fuzz::expectDataErrorOnly(
      [&] { (void)occsweep::decodePoses(occsweep::fuzz::asText(data + 1, size - 1), "fuzz.txt", format); });
}
