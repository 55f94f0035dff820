// Provenance recorded by value and checked when read (docs/dataset-format.md, "Provenance").
#include "occsweep/eval/provenance.hpp"

#include <algorithm>
#include <cstdint>

#include "occsweep/io/data_error.hpp"

namespace occsweep {
namespace {

template <class T>
void feedValues(Fnv1a& h, const T* values, std::size_t count) {
  h.feed(std::string_view(reinterpret_cast<const char*>(values), count * sizeof(T)));
}

void feedPoint(Fnv1a& h, const octomap::point3d& p) {
  const float xyz[3] = {p.x(), p.y(), p.z()};
  feedValues(h, xyz, 3);
}

bool isHash(const nlohmann::json& v) {
  if (!v.is_string()) return false;
  const auto& s = v.get_ref<const std::string&>();
  const auto lower_hex = [](char c) { return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'); };
  return s.size() == 16 && std::all_of(s.begin(), s.end(), lower_hex);
}

}  // namespace

void recordTruthAndRegion(nlohmann::json& provenance, const TruthSources& truth, const AxisBox& region) {
  Fnv1a h;
  const std::uint64_t counts[3] = {truth.boxes.size(), truth.mesh.size(), truth.points.size()};
  feedValues(h, counts, 3);
  for (const AxisBox& b : truth.boxes) {
    feedValues(h, b.min.data(), 3);
    feedValues(h, b.max.data(), 3);
  }
  for (const Triangle& t : truth.mesh)
    for (const auto& v : t.v) feedPoint(h, v);
  for (const auto& p : truth.points) feedPoint(h, p);
  provenance["truth"] = nlohmann::json::array({h.hex()});
  provenance["region"] = contentHash(nlohmann::json{region.min, region.max}.dump());
}

void recordPoints(nlohmann::json& provenance, const PointCloudSet& scans) {
  Fnv1a h;
  const std::uint64_t count = scans.size();
  feedValues(h, &count, 1);
  for (const Scan& scan : scans) {
    const std::uint64_t points = scan.points.size();
    feedValues(h, &points, 1);
    feedPoint(h, scan.origin);
    for (const auto& p : scan.points) feedPoint(h, p);
  }
  provenance["points"] = h.hex();
}

void checkProvenance(const nlohmann::json& provenance, const std::filesystem::path& file, const std::string& field) {
  const std::string fix = ": remove it (compare then counts the data set by its name) or write the data set anew "
                          "with occsweep (docs/dataset-format.md, \"Provenance\")";
  if (!provenance.is_object()) throw DataError(file, field, "must be an object of content hashes" + fix);
  for (const auto& [key, value] : provenance.items()) {
    const bool list = key == "inputs" || key == "poses" || key == "truth";
    if (!list && key != "region" && key != "scene" && key != "points")
      throw DataError(file, field + "." + key,
                      "is not a provenance field (inputs, poses, truth, region, scene, points)" + fix);
    if (list ? !value.is_array() || !std::all_of(value.begin(), value.end(), isHash) : !isHash(value))
      throw DataError(file, field + "." + key,
                      std::string(list ? "must be an array of content hashes" : "must be a content hash") +
                          ", 16 lowercase hex digits each" + fix);
  }
}

}  // namespace occsweep
