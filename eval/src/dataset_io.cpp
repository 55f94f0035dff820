#include <algorithm>
#include <limits>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <set>
#include <sstream>
#include <sys/stat.h>
#include <unistd.h>

#include "occsweep/core/limits.hpp"
#include "occsweep/io/data_error.hpp"
#include "occsweep/eval/dataset.hpp"
#include "occsweep/io/fnv1a.hpp"
#include "occsweep/io/output_file.hpp"
#include "occsweep/io/bounded_read.hpp"
#include "occsweep/eval/sensor_view_json.hpp"
#include "occsweep/eval/json_input.hpp"
#include "occsweep/eval/provenance.hpp"

namespace occsweep {

AxisBox boundingBox(const PointCloudSet& scans) {
  // In float, converted once at the end: the same box (float to double is exact and keeps the order), without
  // a conversion per coordinate.
  constexpr float inf = std::numeric_limits<float>::infinity();
  std::array<float, 3> lo{inf, inf, inf}, hi{-inf, -inf, -inf};
  auto grow = [&lo, &hi](const octomap::point3d& p) {
    for (std::size_t a = 0; a < 3; ++a) lo[a] = std::min(lo[a], p(unsigned(a))), hi[a] = std::max(hi[a], p(unsigned(a)));
  };
  for (const auto& s : scans) {
    grow(s.origin);
    for (const auto& p : s.points) grow(p);
  }
  AxisBox box;
  for (std::size_t a = 0; a < 3; ++a) box.min[a] = lo[a], box.max[a] = hi[a];
  return box;
}


namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr const char* kFormat = "occsweep-dataset";
constexpr int kVersion = 1;
constexpr std::uint64_t kMaxPointsPerFile = std::uint64_t(1) << 31;  // 24 GiB of float32: refuse beyond

void writeFloats(const fs::path& file, const std::vector<octomap::point3d>& pts) {
  std::string bytes;
  bytes.reserve(pts.size() * 12);
  for (const auto& p : pts) {
    const float xyz[3] = {p.x(), p.y(), p.z()};
    bytes.append(reinterpret_cast<const char*>(xyz), sizeof xyz);  // little-endian hosts only (x86-64, arm64)
  }
  writeFileChecked(file, bytes);
}

std::vector<octomap::point3d> readFloats(const fs::path& file, std::uint64_t expected, const std::string& field) {
  requireRegularFile(file);
  std::error_code ec;
  const auto size = fs::file_size(file, ec);
  if (ec) throw DataError(file, field, "cannot read its size: " + ec.message());
  if (expected > kMaxPointsPerFile) throw DataError(file, field, "claims an absurd point count");
  if (size != expected * 12)
    throw DataError(file, field,
                    "holds " + std::to_string(size) + " bytes, expected " + std::to_string(expected * 12) +
                        " (" + std::to_string(expected) + " points of 3 float32): truncated or wrong count");
  std::ifstream in(file, std::ios::binary);
  std::vector<float> raw(expected * 3);
  in.read(reinterpret_cast<char*>(raw.data()), std::streamsize(raw.size() * sizeof(float)));
  if (!in) throw DataError(file, field, "cannot read");
  std::vector<octomap::point3d> pts(expected);
  for (std::uint64_t i = 0; i < expected; ++i) {
    for (int a = 0; a < 3; ++a)
      if (!std::isfinite(raw[i * 3 + a]))
        throw DataError(file, field, "point " + std::to_string(i) + " has a NaN or infinite coordinate");
    pts[i] = octomap::point3d(raw[i * 3], raw[i * 3 + 1], raw[i * 3 + 2]);
  }
  return pts;
}

json vec(const octomap::point3d& p) { return json::array({p.x(), p.y(), p.z()}); }
json vec(const std::array<double, 3>& p) { return json::array({p[0], p[1], p[2]}); }

// Typed access to manifest fields with errors that name the field.
struct Manifest {
  fs::path file;
  const json& at(const json& obj, const std::string& key, const std::string& where) const {
    if (!obj.is_object() || !obj.contains(key)) throw DataError(file, where + key, "field is missing");
    return obj.at(key);
  }
  std::array<double, 3> triple(const json& v, const std::string& where) const {
    if (!v.is_array() || v.size() != 3) throw DataError(file, where, "must be an array of 3 numbers");
    std::array<double, 3> out{};
    for (int a = 0; a < 3; ++a) {
      if (!v[a].is_number()) throw DataError(file, where, "must be an array of 3 numbers");
      out[a] = v[a].get<double>();
      if (!std::isfinite(out[a])) throw DataError(file, where, "must be finite");
    }
    return out;
  }
  std::uint64_t count(const json& v, const std::string& where) const {
    if (!v.is_number_unsigned()) throw DataError(file, where, "must be a non-negative integer");
    return v.get<std::uint64_t>();
  }
  /// The file a manifest path names, refused unless it is inside the data-set folder once symbolic links are
  /// resolved (docs/dataset-format.md): an absolute path, a ".." component or a link leading out is refused; a
  /// name that merely contains two dots ("a..b.f32") is fine.
  fs::path inside(const json& v, const std::string& where) const {
    if (!v.is_string() || v.get<std::string>().empty()) throw DataError(file, where, "must be a file name");
    const fs::path p = v.get<std::string>();
    const auto dotdot = std::find(p.begin(), p.end(), fs::path(".."));
    if (p.is_absolute() || dotdot != p.end())
      throw DataError(file, where, "\"" + p.string() + "\" must be a relative path inside the data set folder");
    std::error_code ec;
    const fs::path folder = fs::canonical(file.parent_path(), ec);
    const fs::path target = ec ? fs::path() : fs::weakly_canonical(folder / p, ec);
    if (ec) throw DataError(file, where, "\"" + p.string() + "\" cannot be resolved: " + ec.message());
    const auto [f, t] = std::mismatch(folder.begin(), folder.end(), target.begin(), target.end());
    if (f != folder.end())
      throw DataError(file, where, "\"" + p.string() + "\" leads out of the data set folder (to " + target.string() +
                                       ", through a symbolic link)");
    return file.parent_path() / p;  // as the user wrote it, for messages
  }
  AxisBox box(const json& v, const std::string& where) const {
    AxisBox b{triple(at(v, "min", where + "."), where + ".min"), triple(at(v, "max", where + "."), where + ".max")};
    for (int a = 0; a < 3; ++a)
      if (b.min[a] > b.max[a]) throw DataError(file, where, "min must be <= max on every axis");
    return b;
  }
};

// The points the manifest lists, summed before any scan is read: a small manifest naming one scan thousands of
// times is refused before its scans fill memory.
void checkPointTotal(const Manifest& mf, const json& scans) {
  std::uint64_t total = 0;
  for (std::size_t i = 0; i < scans.size(); ++i) {
    const std::string where = "scans[" + std::to_string(i) + "]";
    const auto n = mf.count(mf.at(scans[i], "points", where + "."), where + ".points");
    total = n > UINT64_MAX - total ? UINT64_MAX : total + n;
  }
  try {
    checkLimit("points of all scans", total, limits().points, "--max-points");
  } catch (const LimitError& e) {
    throw DataError(mf.file, "scans", e.what());
  }
}

// Binary files of a manifest in hashing order.
std::vector<fs::path> binaryFiles(const json& m) {
  std::vector<fs::path> files;
  for (const auto& s : m.at("scans")) files.emplace_back(s.at("file").get<std::string>());
  const auto& t = m.at("truth");
  for (const char* key : {"mesh_file", "points_file"})
    if (t.contains(key) && t.at(key).is_string()) files.emplace_back(t.at(key).get<std::string>());
  return files;
}

}  // namespace

void writeDataset(const Dataset& d, const fs::path& dir) {
  OutputFolder folder(dir);
  const fs::path& tmp = folder.path();
  makeFolderChecked(tmp / "scans");
  json m;
  m["format"] = kFormat;
  m["version"] = kVersion;
  m["name"] = d.name;
  m["scans"] = json::array();
  for (std::size_t i = 0; i < d.scans.size(); ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "scans/%06zu.f32", i);
    writeFloats(tmp / name, d.scans[i].points);
    json scan = {{"file", name}, {"origin", vec(d.scans[i].origin)}, {"points", d.scans[i].points.size()}};
    // Only when recorded: a data set without views keeps its manifest, and its content hash, byte for byte.
    if (d.scans[i].view) scan["view"] = sensorViewJson(*d.scans[i].view);
    m["scans"].push_back(std::move(scan));
  }
  json truth = {{"boxes", json::array()}};
  for (const auto& b : d.truth.boxes) truth["boxes"].push_back({{"min", vec(b.min)}, {"max", vec(b.max)}});
  if (!d.truth.mesh.empty()) {
    std::vector<octomap::point3d> v;
    for (const auto& t : d.truth.mesh) v.insert(v.end(), t.v.begin(), t.v.end());
    writeFloats(tmp / "truth_mesh.f32", v);
    truth["mesh_file"] = "truth_mesh.f32";
    truth["mesh_triangles"] = d.truth.mesh.size();
  }
  if (!d.truth.points.empty()) {
    writeFloats(tmp / "truth_points.f32", d.truth.points);
    truth["points_file"] = "truth_points.f32";
    truth["points"] = d.truth.points.size();
  }
  m["truth"] = truth;
  m["region"] = {{"min", vec(d.region.min)}, {"max", vec(d.region.max)}};
  m["source"] = d.source;
  writeFileChecked(tmp / "manifest.json", m.dump(1) + '\n');
  folder.commit();
}

// The files a data set's manifest names: manifest.json, scans/ and each binary file (binaryFiles).
static std::set<fs::path> datasetFiles(const json& manifest) {
  std::set<fs::path> files = {"manifest.json", "scans"};
  for (const fs::path& f : binaryFiles(manifest)) files.insert(f.lexically_normal());
  return files;
}

static bool isDatasetFolder(const fs::path& dir) {
  // Only what writeDataset wrote for this manifest: a folder that also holds a user's file (even a
  // scans/000099.f32 the manifest does not name) is not occsweep's to remove (docs/io.md, "Ownership").
  std::set<fs::path> own;
  try {
    const json m = readJsonFile(dir / "manifest.json");
    if (m.value("format", "") != kFormat) return false;
    own = datasetFiles(m);
  } catch (const std::exception&) {
    return false;
  }
  std::error_code ec;
  for (fs::recursive_directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const fs::path rel = it->path().lexically_relative(dir);
    const fs::file_type type = it->symlink_status(ec).type();
    const fs::file_type expected = rel == "scans" ? fs::file_type::directory : fs::file_type::regular;
    if (!own.contains(rel) || type != expected) return false;
  }
  return !ec;
}

ReplaceableOutput datasetOutput() { return {"data set folder", isDatasetFolder}; }

Dataset readDataset(const fs::path& dir) {
  const fs::path file = dir / "manifest.json";
  if (!fs::is_directory(dir)) throw DataError(dir, "", "data set folder is missing");
  const json m = readJsonFile(file);
  const Manifest mf{file};
  if (!m.is_object()) throw DataError(file, "", "must be a JSON object");
  if (mf.at(m, "format", "") != kFormat) throw DataError(file, "format", std::string("must be \"") + kFormat + "\"");
  if (mf.at(m, "version", "") != kVersion)
    throw DataError(file, "version", "unsupported version (this occsweep reads " + std::to_string(kVersion) + ")");
  Dataset d;
  const json& name = mf.at(m, "name", "");
  if (!name.is_string() || name.get<std::string>().empty()) throw DataError(file, "name", "must be a non-empty string");
  d.name = name.get<std::string>();
  const json& scans = mf.at(m, "scans", "");
  if (!scans.is_array() || scans.empty()) throw DataError(file, "scans", "must be a non-empty array");
  checkPointTotal(mf, scans);
  for (std::size_t i = 0; i < scans.size(); ++i) {
    const std::string where = "scans[" + std::to_string(i) + "]";
    const json& s = scans[i];
    Scan scan;
    const auto o = mf.triple(mf.at(s, "origin", where + "."), where + ".origin");
    scan.origin = octomap::point3d(float(o[0]), float(o[1]), float(o[2]));
    const auto n = mf.count(mf.at(s, "points", where + "."), where + ".points");
    if (n == 0) throw DataError(file, where + ".points", "an empty scan (0 points) is not allowed");
    if (s.contains("view")) scan.view = sensorViewFromJson(s.at("view"), file, where + ".view");
    scan.points = readFloats(mf.inside(mf.at(s, "file", where + "."), where + ".file"), n, where);
    d.scans.push_back(std::move(scan));
  }
  const json& truth = mf.at(m, "truth", "");
  if (!truth.is_object()) throw DataError(file, "truth", "must be an object (boxes, mesh_file, points_file)");
  if (truth.contains("boxes")) {
    const json& boxes = truth.at("boxes");
    if (!boxes.is_array()) throw DataError(file, "truth.boxes", "must be an array");
    for (std::size_t i = 0; i < boxes.size(); ++i)
      d.truth.boxes.push_back(mf.box(boxes[i], "truth.boxes[" + std::to_string(i) + "]"));
  }
  if (truth.contains("mesh_file")) {
    const auto n = mf.count(mf.at(truth, "mesh_triangles", "truth."), "truth.mesh_triangles");
    if (n > kMaxPointsPerFile / 3) throw DataError(file, "truth.mesh_triangles", "claims an absurd count");
    const auto v = readFloats(mf.inside(truth.at("mesh_file"), "truth.mesh_file"), n * 3, "truth.mesh_file");
    for (std::uint64_t t = 0; t < n; ++t) d.truth.mesh.push_back(Triangle{{v[t * 3], v[t * 3 + 1], v[t * 3 + 2]}});
  }
  if (truth.contains("points_file")) {
    const auto n = mf.count(mf.at(truth, "points", "truth."), "truth.points");
    d.truth.points = readFloats(mf.inside(truth.at("points_file"), "truth.points_file"), n, "truth.points_file");
  }
  d.region = mf.box(mf.at(m, "region", ""), "region");
  if (m.contains("source")) d.source = m.at("source");
  if (d.source.is_object() && d.source.contains("provenance"))
    checkProvenance(d.source.at("provenance"), file, "source.provenance");
  return d;
}

GroundTruth groundTruthOf(const Dataset& d, const fs::path& dir, double resolution) {
  try {
    return makeGroundTruth(d.truth, d.region, resolution);
  } catch (const LimitError& e) {
    throw DataError(dir / "manifest.json", "", e.what());
  } catch (const std::invalid_argument& e) {
    std::string why = e.what();
    if (why.rfind("ground truth: ", 0) == 0) why.erase(0, 14);
    const auto& r = d.region;
    throw DataError(dir / "manifest.json", "region",
                    why + " (min " + std::to_string(r.min[0]) + " " + std::to_string(r.min[1]) + " " +
                        std::to_string(r.min[2]) + ", max " + std::to_string(r.max[0]) + " " +
                        std::to_string(r.max[1]) + " " + std::to_string(r.max[2]) + ", resolution " +
                        std::to_string(resolution) + "): widen the region (import truth --region) or use a finer "
                        "--resolution");
  }
}

std::string datasetContentHash(const fs::path& dir) {
  Fnv1a h;
  h.feedFile(dir / "manifest.json");
  for (const auto& f : binaryFiles(readJsonFile(dir / "manifest.json"))) h.feedFile(dir / f);
  return h.hex();
}

}  // namespace occsweep
