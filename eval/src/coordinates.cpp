#include "occsweep/eval/coordinates.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "occsweep/io/data_error.hpp"

namespace occsweep {
namespace fs = std::filesystem;

namespace {

constexpr double kKeyHalf = 32768.0;  // liboctomap's tree_max_val for 16-bit keys

std::string number(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}

std::string pointText(const octomap::point3d& p) {
  return "(" + number(p.x()) + ", " + number(p.y()) + ", " + number(p.z()) + ")";
}

bool finitePoint(const octomap::point3d& p) {
  return std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z());
}

// Checks points against the key range; returns the index of the first outside, or -1.
long long firstOutside(const std::vector<octomap::point3d>& pts, const KeyRange& range) {
  for (std::size_t i = 0; i < pts.size(); ++i)
    if (!range.holds(pts[i].x()) || !range.holds(pts[i].y()) || !range.holds(pts[i].z())) return (long long)i;
  return -1;
}

std::string shiftText(const std::array<double, 3>& s) {
  return number(s[0]) + " " + number(s[1]) + " " + number(s[2]);
}

struct RangeCheck {
  fs::path manifest;
  KeyRange range;
  std::string remedy;
  void points(const std::vector<octomap::point3d>& pts, const std::string& where) const {
    const long long i = firstOutside(pts, range);
    if (i >= 0)
      throw DataError(manifest, where, "point " + std::to_string(i) + " " + pointText(pts[std::size_t(i)]) +
                                           " is outside OctoMap's key range " + range.text() + remedy);
  }
  void box(const AxisBox& b, const std::string& where, const std::string& box_remedy) const {
    for (int a = 0; a < 3; ++a)
      if (!range.holds(b.min[std::size_t(a)]) || !range.holds(b.max[std::size_t(a)]))
        throw DataError(manifest, where, "[" + number(b.min[std::size_t(a)]) + ", " + number(b.max[std::size_t(a)]) +
                                             "] on axis " + "xyz"[a] + " is outside OctoMap's key range " +
                                             range.text() + box_remedy);
  }
};

}  // namespace

void requireFinitePoints(const std::vector<octomap::point3d>& pts, const std::string& file, const std::string& where,
                         const std::string& hint) {
  for (std::size_t i = 0; i < pts.size(); ++i)
    if (!finitePoint(pts[i]))
      throw DataError(file, where.empty() ? "point " + std::to_string(i) : where + ": point " + std::to_string(i),
                      "a coordinate is beyond float32's range (|v| > 3.4e38) once computed, so it cannot be stored" +
                          (hint.empty() ? "" : " (" + hint + ")"));
}

void requireFiniteScan(const Scan& scan, const std::string& file, const std::string& where, const std::string& hint) {
  if (!finitePoint(scan.origin))
    throw DataError(file, where.empty() ? "origin" : where + ": origin",
                    "the sensor origin is beyond float32's range (|v| > 3.4e38), so it cannot be stored" +
                        (hint.empty() ? "" : " (" + hint + ")"));
  requireFinitePoints(scan.points, file, where, hint);
}

bool KeyRange::holds(double c) const {
  const double key = std::floor(c * (1.0 / resolution));  // as liboctomap: floor(resolution_factor * c)
  return key >= -kKeyHalf && key < kKeyHalf;
}

std::string KeyRange::text() const {
  std::string text = "[";  // appended piece by piece: "[" + std::string trips GCC 12's -Wrestrict false positive
  text += number(lowest);
  text += ", ";
  text += number(highest);
  text += ") m at resolution ";
  text += number(resolution);
  return text + " m";
}

KeyRange keyRange(double resolution) { return {resolution, -kKeyHalf * resolution, kKeyHalf * resolution}; }

std::array<double, 3> centringShift(const PointCloudSet& scans, const KeyRange& range) {
  return centringShift(boundingBox(scans), range);
}

std::array<double, 3> centringShift(const AxisBox& b, const KeyRange& range) {
  std::array<double, 3> s{0, 0, 0};
  for (std::size_t a = 0; a < 3; ++a)
    if (!range.holds(b.min[a]) || !range.holds(b.max[a])) s[a] = 0.0 - std::round((b.min[a] + b.max[a]) / 2);
  return s;
}

void requireInKeyRange(const Dataset& d, const fs::path& dir, double resolution) {
  const KeyRange range = keyRange(resolution);
  const fs::path manifest = dir / "manifest.json";
  const AxisBox b = boundingBox(d.scans);
  // holds() is monotone (floor of a product with a positive factor): when the box's corners are in range, so is
  // every point and origin; only otherwise are they checked one by one, to name the first outside.
  bool corners_hold = true;
  for (std::size_t a = 0; a < 3; ++a) corners_hold = corners_hold && range.holds(b.min[a]) && range.holds(b.max[a]);
  if (!corners_hold) {
    std::string scan_remedy = ": nothing outside it can be mapped (liboctomap drops it)";
    bool fits = true;
    for (std::size_t a = 0; a < 3; ++a) fits &= b.max[a] - b.min[a] < range.highest - range.lowest - 2 * resolution;
    if (fits)
      scan_remedy += "; re-import with --shift " + shiftText(centringShift(b, range)) +
                     " (moves the scans' centre to 0, docs/import.md) or map at a coarser --resolution";
    else
      scan_remedy += "; the scans span more than the range: map at a coarser --resolution";
    const RangeCheck scans{manifest, range, scan_remedy};
    for (std::size_t i = 0; i < d.scans.size(); ++i) {
      const std::string where = "scans[" + std::to_string(i) + "]";
      scans.points({d.scans[i].origin}, where + ".origin");
      scans.points(d.scans[i].points, where + " (" + std::to_string(d.scans[i].points.size()) + " points)");
    }
  }
  const RangeCheck truth{manifest, range, ": its voxels cannot be counted"};
  for (std::size_t i = 0; i < d.truth.boxes.size(); ++i)
    truth.box(d.truth.boxes[i], "truth.boxes[" + std::to_string(i) + "]",
              ": its voxels cannot be counted; clip the box to the region");
  std::vector<octomap::point3d> vertices;
  for (const auto& t : d.truth.mesh) vertices.insert(vertices.end(), t.v.begin(), t.v.end());
  truth.points(vertices, "truth.mesh_file (vertex)");
  truth.points(d.truth.points, "truth.points_file");
  truth.box(d.region, "region", ": the region would be folded into the range; give a region inside it "
                                "(occsweep import truth --region)");
}

std::array<double, 3> recordedShift(const Dataset& d) {
  std::array<double, 3> s{0, 0, 0};
  if (d.source.is_object() && d.source.contains("shift") && d.source.at("shift").is_array() &&
      d.source.at("shift").size() == 3)
    for (std::size_t a = 0; a < 3; ++a)
      if (d.source.at("shift")[a].is_number()) s[a] = d.source.at("shift")[a].get<double>();
  return s;
}

namespace {

octomap::point3d moved(const octomap::point3d& p, const std::array<double, 3>& s) {
  return octomap::point3d(float(double(p.x()) + s[0]), float(double(p.y()) + s[1]), float(double(p.z()) + s[2]));
}

void movePoints(std::vector<octomap::point3d>& pts, const std::array<double, 3>& s) {
  for (auto& p : pts) p = moved(p, s);
}

void moveBox(AxisBox& b, const std::array<double, 3>& s) {
  for (std::size_t a = 0; a < 3; ++a) {
    b.min[a] += s[a];
    b.max[a] += s[a];
  }
}

}  // namespace

void shiftTruth(TruthSources& t, const std::array<double, 3>& s, const std::string& file) {
  for (auto& b : t.boxes) moveBox(b, s);
  for (auto& tri : t.mesh)
    for (auto& v : tri.v) v = moved(v, s);
  movePoints(t.points, s);
  std::vector<octomap::point3d> vertices;
  for (const auto& tri : t.mesh) vertices.insert(vertices.end(), tri.v.begin(), tri.v.end());
  requireFinitePoints(vertices, file, "mesh vertex", "after the data set's shift " + shiftText(s));
  requireFinitePoints(t.points, file, "", "after the data set's shift " + shiftText(s));
}

void applyShift(Dataset& d, const std::array<double, 3>& s) {
  for (std::size_t a = 0; a < 3; ++a)
    if (!std::isfinite(s[a])) throw std::invalid_argument("--shift: must be 3 finite numbers");
  for (std::size_t i = 0; i < d.scans.size(); ++i) {
    d.scans[i].origin = moved(d.scans[i].origin, s);
    movePoints(d.scans[i].points, s);
    try {
      requireFiniteScan(d.scans[i], "scan " + std::to_string(i), "", "");
    } catch (const DataError& e) {
      throw std::invalid_argument("--shift " + shiftText(s) + " moves " + e.what());
    }
  }
  shiftTruth(d.truth, s, "--shift " + shiftText(s));
  moveBox(d.region, s);
  recordShift(d, s);
}

void recordShift(Dataset& d, const std::array<double, 3>& s) {
  const auto before = recordedShift(d);
  d.source["shift"] = {before[0] + s[0], before[1] + s[1], before[2] + s[2]};
}

}  // namespace occsweep
