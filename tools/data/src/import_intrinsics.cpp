#include "occsweep/data/import_intrinsics.hpp"

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "occsweep/data/byte_reader.hpp"
#include "occsweep/eval/json_input.hpp"
#include "occsweep/io/bounded_read.hpp"
#include "occsweep/io/data_error.hpp"

namespace occsweep {
namespace fs = std::filesystem;

namespace {

constexpr const char* kMatrixForm = "a camera matrix is fx 0 cx / 0 fy cy / 0 0 1";

/// Replica's cam_params.json (NICE-SLAM's download): {"camera": {"w", "h", "fx", "fy", "cx", "cy", "scale"}}.
CameraIntrinsics cameraObject(const nlohmann::json& root, const fs::path& file) {
  if (!root.is_object() || !root.contains("camera") || !root.at("camera").is_object())
    throw DataError(file, "camera", "missing: the intrinsics are read from {\"camera\": {\"fx\": ..., \"fy\": ..., "
                                    "\"cx\": ..., \"cy\": ...}} (Replica's cam_params.json)");
  const nlohmann::json& camera = root.at("camera");
  auto field = [&](const char* name, bool required) -> std::optional<double> {
    if (!camera.contains(name)) {
      if (required) throw DataError(file, std::string("camera.") + name, "missing: give it in pixels");
      return std::nullopt;
    }
    if (!camera.at(name).is_number())
      throw DataError(file, std::string("camera.") + name, "must be a number, got " + camera.at(name).dump());
    return camera.at(name).get<double>();
  };
  CameraIntrinsics k{*field("fx", true), *field("fy", true), *field("cx", true), *field("cy", true),
                     field("scale", false), std::nullopt, std::nullopt};
  for (const char* name : {"w", "h"})
    if (const auto size = field(name, false)) {
      if (!(*size >= 1 && *size <= 1e6 && *size == std::floor(*size)))
        throw DataError(file, std::string("camera.") + name, "must be a whole number of pixels >= 1, got " +
                                                                 camera.at(name).dump());
      (name[0] == 'w' ? k.width : k.height) = int(*size);
    }
  if (k.depth_scale && !(*k.depth_scale > 0))
    throw DataError(file, "camera.scale", "must be > 0 (raw depth units per metre; Replica's is 6553.5), got " +
                                              camera.at("scale").dump());
  return k;
}

/// 3DMatch's and 7-Scenes' camera-intrinsics.txt: the 3x3 matrix, row-major, as numpy.savetxt writes it.
CameraIntrinsics cameraMatrix(std::string_view text, const fs::path& file) {
  TextLines lines(text, file);
  std::vector<std::string_view> tok;
  std::vector<double> m;
  while (lines.nextData(tok))
    for (std::size_t i = 0; i < tok.size(); ++i) {
      if (m.size() == 9) lines.fail("more than 9 numbers: " + std::string(kMatrixForm));
      m.push_back(lines.number(tok[i], i, "matrix entry"));
    }
  if (m.size() != 9)
    throw DataError(file, "", "holds " + std::to_string(m.size()) + " numbers, expected 9: " + kMatrixForm);
  const std::array<std::pair<std::size_t, double>, 5> fixed{{{1, 0}, {3, 0}, {6, 0}, {7, 0}, {8, 1}}};
  for (const auto& [at, value] : fixed)
    if (m[at] != value)
      throw DataError(file, "row " + std::to_string(at / 3 + 1) + ", column " + std::to_string(at % 3 + 1),
                      "is " + std::to_string(m[at]) + ", expected " + std::to_string(int(value)) + ": " + kMatrixForm +
                          " (a skewed or projective matrix is not a pinhole occsweep reads)");
  return {m[0], m[4], m[2], m[5], std::nullopt, std::nullopt, std::nullopt};
}

}  // namespace

CameraIntrinsics decodeIntrinsics(std::string_view bytes, const fs::path& file) {
  const std::size_t first = bytes.find_first_not_of(" \t\r\n");
  CameraIntrinsics k = first != std::string_view::npos && bytes[first] == '{'
                           ? cameraObject(parseJsonTextUniqueKeys(bytes, file), file)
                           : cameraMatrix(bytes, file);
  if (!std::isfinite(k.fx) || !std::isfinite(k.fy) || k.fx == 0 || k.fy == 0)
    throw DataError(file, "fx, fy", "focal lengths must be finite and non-zero, got " + std::to_string(k.fx) + ", " +
                                        std::to_string(k.fy));
  if (!std::isfinite(k.cx) || !std::isfinite(k.cy))
    throw DataError(file, "cx, cy", "the principal point must be finite");
  return k;
}

CameraIntrinsics readIntrinsics(const fs::path& file) {
  return decodeIntrinsics(readFileBytes(file, std::uint64_t(1) << 20), file);
}

}  // namespace occsweep
