// libFuzzer: pose files; the first byte's two low bits pick quaternion lines, 4x4 matrices, TUM lines or KITTI
// lines (decodePoses).
#include "fuzz_common.hpp"
#include "occsweep/data/import_pose.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  using occsweep::PoseFormat;
  const PoseFormat formats[] = {PoseFormat::Quaternion, PoseFormat::Matrix, PoseFormat::Tum, PoseFormat::Kitti};
  const PoseFormat format = formats[data[0] & 3];
  return occsweep::fuzz::expectDataErrorOnly(
      [&] { (void)occsweep::decodePoses(occsweep::fuzz::asText(data + 1, size - 1), "fuzz.txt", format); });
}
