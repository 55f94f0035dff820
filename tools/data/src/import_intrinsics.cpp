#include "occsweep/data/import_intrinsics.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <string>
#include <tuple>
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
constexpr const char* kForms =
    "give {\"camera\": {\"w\", \"h\", \"fx\", \"fy\", \"cx\", \"cy\", \"scale\"}} (Replica's cam_params.json) or text "
    "of 9 numbers, the matrix fx 0 cx / 0 fy cy / 0 0 1 (3DMatch's camera-intrinsics.txt)";
/// numpy's round-off: savetxt of a computed matrix writes 1e-17 for its zeros and 1.0000000000000002 for its 1.
constexpr double kRoundOff = 1e-9;
constexpr std::string_view kUtf8Bom = "\xEF\xBB\xBF";

/// The shortest text that reads back to `value`: 1e-06, not std::to_string's 0.000001.
std::string exactly(double value) {
  char text[32];
  return {text, std::to_chars(text, text + sizeof text, value).ptr};
}

/// Replica's cam_params.json (NICE-SLAM's download): {"camera": {"w", "h", "fx", "fy", "cx", "cy", "scale"}}; "scale"
/// may be missing only when --depth-scale gives it: a default would put Replica's 6553.5 units a metre at 1000.
CameraIntrinsics cameraObject(const nlohmann::json& root, const fs::path& file, bool depth_scale_given) {
  if (!root.is_object())
    throw DataError(file, "", std::string("is a JSON ") + root.type_name() + ", not an intrinsics file: " + kForms);
  if (!root.contains("camera") || !root.at("camera").is_object())
    throw DataError(file, "camera", "missing: the intrinsics are read from {\"camera\": {\"w\": ..., \"h\": ..., "
                                    "\"fx\": ..., \"fy\": ..., \"cx\": ..., \"cy\": ...}} (Replica's cam_params.json)");
  const nlohmann::json& camera = root.at("camera");
  auto field = [&](const char* name) -> std::optional<double> {
    if (!camera.contains(name)) return std::nullopt;
    if (!camera.at(name).is_number())
      throw DataError(file, std::string("camera.") + name, "must be a number, got " + camera.at(name).dump());
    return camera.at(name).get<double>();
  };
  auto required = [&](const char* name, const std::string& fix) {
    if (const auto value = field(name)) return *value;
    throw DataError(file, std::string("camera.") + name, "missing: " + fix);
  };
  const std::string pixels = "give it in pixels";
  CameraIntrinsics k{required("fx", pixels), required("fy", pixels), required("cx", pixels), required("cy", pixels),
                     field("scale"), std::nullopt, std::nullopt};
  if (!k.depth_scale && !depth_scale_given)
    (void)required("scale", "give the raw depth units per metre (Replica's is 6553.5), or --depth-scale");
  // The images' size, which every image must have, and the principal point within it: one outside is another
  // camera's, or another image size's (docs/import.md, "Intrinsics files").
  for (const auto& [side, centre, at, size] : {std::tuple{"w", "cx", k.cx, &k.width}, {"h", "cy", k.cy, &k.height}}) {
    const double pixels = required(side, std::string("give the images' ") + (side[0] == 'w' ? "width" : "height") +
                                             " in pixels (Replica's cam_params.json has both)");
    if (!(pixels >= 1 && pixels <= 1e6 && pixels == std::floor(pixels)))
      throw DataError(file, std::string("camera.") + side, "must be a whole number of pixels >= 1, got " +
                                                               camera.at(side).dump());
    if (!(at >= 0 && at <= pixels))
      throw DataError(file, std::string("camera.") + centre, "is " + exactly(at) + ", outside the image's 0 to " +
                                                                 exactly(pixels) + " pixels (camera." + side +
                                                                 "): is the file another camera's, or for another "
                                                                 "image size?");
    *size = int(pixels);
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
      const double entry = lines.number(tok[i], i, "matrix entry");
      if (m.size() == 9) lines.fail("more than 9 numbers: " + std::string(kMatrixForm));
      m.push_back(entry);
    }
  if (m.size() != 9)
    throw DataError(file, "", "holds " + std::to_string(m.size()) + " numbers, expected 9: " + kMatrixForm);
  const std::array<std::pair<std::size_t, double>, 5> fixed{{{1, 0}, {3, 0}, {6, 0}, {7, 0}, {8, 1}}};
  for (const auto& [at, value] : fixed) {
    // Within round-off of its value, relative to its row's largest entry (docs/import.md, "Intrinsics files").
    const std::size_t row = at / 3 * 3;
    const double row_scale = std::max({std::abs(m[row]), std::abs(m[row + 1]), std::abs(m[row + 2])});
    if (!(std::abs(m[at] - value) <= kRoundOff * row_scale))
      throw DataError(file, "row " + std::to_string(at / 3 + 1) + ", column " + std::to_string(at % 3 + 1),
                      "is " + exactly(m[at]) + ", expected " + std::to_string(int(value)) + ": " + kMatrixForm +
                          " (a skewed or projective matrix is not a pinhole occsweep reads)");
  }
  return {m[0], m[4], m[2], m[5], std::nullopt, std::nullopt, std::nullopt};
}

}  // namespace

CameraIntrinsics decodeIntrinsics(std::string_view bytes, const fs::path& file, bool depth_scale_given) {
  if (bytes.starts_with(kUtf8Bom)) bytes.remove_prefix(kUtf8Bom.size());  // as Windows editors save text
  const std::size_t first = bytes.find_first_not_of(" \t\r\n");
  CameraIntrinsics k = first != std::string_view::npos && (bytes[first] == '{' || bytes[first] == '[')
                           ? cameraObject(parseJsonTextUniqueKeys(bytes, file), file, depth_scale_given)
                           : cameraMatrix(bytes, file);
  if (!std::isfinite(k.fx) || !std::isfinite(k.fy) || k.fx == 0 || k.fy == 0)
    throw DataError(file, "fx, fy", "focal lengths must be finite and non-zero, got " + std::to_string(k.fx) + ", " +
                                        std::to_string(k.fy));
  if (!std::isfinite(k.cx) || !std::isfinite(k.cy))
    throw DataError(file, "cx, cy", "the principal point must be finite");
  return k;
}

CameraIntrinsics readIntrinsics(const fs::path& file, bool depth_scale_given) {
  return decodeIntrinsics(readFileBytes(file, std::uint64_t(1) << 20), file, depth_scale_given);
}

}  // namespace occsweep
