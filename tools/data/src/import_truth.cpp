#include "occsweep/data/import_truth.hpp"

#include <cctype>
#include <algorithm>
#include <cmath>
#include <limits>

#include <nlohmann/json.hpp>

#include "occsweep/eval/coordinates.hpp"
#include "occsweep/io/bounded_read.hpp"
#include "occsweep/data/import_cloud.hpp"
#include "occsweep/eval/json_input.hpp"

namespace occsweep {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::array<double, 3> triple(const json& v, const fs::path& file, const std::string& where) {
  if (!v.is_array() || v.size() != 3) throw DataError(file, where, "must be an array of 3 numbers");
  std::array<double, 3> out{};
  for (std::size_t a = 0; a < 3; ++a) {
    if (!v[a].is_number()) throw DataError(file, where, "must be an array of 3 numbers");
    out[a] = v[a].get<double>();
    if (!std::isfinite(out[a])) throw DataError(file, where, "must be finite");
  }
  return out;
}

}  // namespace

AxisBox truthRegion(const TruthSources& truth) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  AxisBox box{{inf, inf, inf}, {-inf, -inf, -inf}};
  auto grow = [&box](std::size_t a, double lo, double hi) {
    box.min[a] = std::min(box.min[a], lo);
    box.max[a] = std::max(box.max[a], hi);
  };
  for (std::size_t a = 0; a < 3; ++a) {
    for (const AxisBox& b : truth.boxes) grow(a, b.min[a], b.max[a]);
    for (const Triangle& t : truth.mesh)
      for (const auto& v : t.v) grow(a, v(int(a)), v(int(a)));
    for (const auto& p : truth.points) grow(a, p(int(a)), p(int(a)));
    box.min[a] -= kTruthRegionMargin;
    box.max[a] += kTruthRegionMargin;
  }
  return box;
}

std::vector<AxisBox> decodeTruthBoxes(std::string_view text, const fs::path& file) {
  json j = parseJsonText(text, file);
  if (j.is_object() && j.contains("boxes")) j = j.at("boxes");
  if (!j.is_array()) throw DataError(file, "", "must be a list of boxes or an object with a \"boxes\" list");
  std::vector<AxisBox> boxes;
  for (std::size_t i = 0; i < j.size(); ++i) {
    const std::string where = "boxes[" + std::to_string(i) + "]";
    const json& b = j[i];
    if (!b.is_object() || !b.contains("min") || !b.contains("max"))
      throw DataError(file, where, "must be an object with \"min\" and \"max\"");
    AxisBox box{triple(b.at("min"), file, where + ".min"), triple(b.at("max"), file, where + ".max")};
    for (std::size_t a = 0; a < 3; ++a)
      if (box.min[a] > box.max[a]) throw DataError(file, where, "min must be <= max on every axis");
    boxes.push_back(box);
  }
  return boxes;
}

TruthSources decodeTruth(std::string_view bytes, const fs::path& file, const std::array<double, 3>& shift) {
  std::string ext = file.extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  CloudPlacement at;  // the identity pose: truth is in the recording's frame, like the scans before the shift
  at.shift = shift;
  TruthSources t;
  if (ext == ".json") {
    t.boxes = decodeTruthBoxes(bytes, file);
    for (std::size_t i = 0; i < t.boxes.size(); ++i)
      for (std::size_t a = 0; a < 3; ++a) {
        AxisBox& box = t.boxes[i];
        box.min[a] += shift[a], box.max[a] += shift[a];
        if (!std::isfinite(box.min[a]) || !std::isfinite(box.max[a]))
          throw DataError(file, "boxes[" + std::to_string(i) + "]", "is not finite after the data set's shift");
      }
  } else if (ext == ".ply") {
    PlyData ply = decodePly(bytes, file, at);
    if (!ply.triangles.empty()) t.mesh = std::move(ply.triangles);
    else t.points = std::move(ply.vertices);
  } else if (ext == ".pcd") {
    t.points = decodePcd(bytes, file, nullptr, at);
  } else {
    throw DataError(file, "", "unknown ground-truth format: expected .ply (mesh or points), .pcd or .json (boxes)");
  }
  if (t.boxes.empty() && t.mesh.empty() && t.points.empty()) throw DataError(file, "", "holds no ground truth");
  std::vector<octomap::point3d> vertices;
  for (const auto& triangle : t.mesh) vertices.insert(vertices.end(), triangle.v.begin(), triangle.v.end());
  requireFinitePoints(vertices, file.string(), "mesh vertex");
  requireFinitePoints(t.points, file.string(), "");
  return t;
}

TruthSources readTruth(const fs::path& file, const std::array<double, 3>& shift) {
  return decodeTruth(readFileBytes(file), file, shift);
}

}  // namespace occsweep
