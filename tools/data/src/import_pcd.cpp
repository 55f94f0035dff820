// PCD v0.7 (the Point Cloud Library's format): header lines up to DATA, then ascii lines or packed binary points.
#include <cctype>
#include <cmath>
#include <limits>
#include <string>

#include "occsweep/io/bounded_read.hpp"
#include "occsweep/data/import_cloud.hpp"
#include "occsweep/data/byte_reader.hpp"

namespace occsweep {
namespace {

struct Field {
  std::string name;
  int size = 4, count = 1;
  char kind = 'f';  // PCD TYPE F, I, U lower-cased
};

struct PcdHeader {
  std::vector<Field> fields;
  std::uint64_t points = 0;
  bool binary = false;
  std::size_t body = 0, body_line = 0;
  int xyz[3] = {-1, -1, -1};            // field index of x, y, z
  std::size_t offset[3] = {0, 0, 0};    // byte offset (binary) or column (ascii) of x, y, z
  std::size_t stride = 0, columns = 0;  // bytes and values a point
};

std::uint64_t unsignedField(const TextLines& lines, std::string_view tok, const char* key) {
  std::uint64_t v = 0;
  if (!parseUnsigned(tok, v)) lines.fail(std::string(key) + " must be a non-negative integer");
  return v;
}

PcdHeader parsePcdHeader(std::string_view bytes, const std::filesystem::path& file) {
  TextLines lines(bytes, file);
  std::vector<std::string_view> tok;
  PcdHeader h;
  std::uint64_t width = 0, height = 1;
  bool have_points = false, have_data = false, have_width = false;
  std::vector<std::string_view> sizes, types, counts;
  while (!have_data && lines.nextData(tok)) {
    const auto key = tok[0];
    const std::vector<std::string_view> args(tok.begin() + 1, tok.end());
    if (key == "VERSION" || key == "VIEWPOINT") continue;  // VIEWPOINT is not used: poses come from the pose list
    if (key == "FIELDS") {
      for (auto a : args) h.fields.push_back(Field{std::string(a)});
    } else if (key == "SIZE") sizes = args;
    else if (key == "TYPE") types = args;
    else if (key == "COUNT") counts = args;
    else if (key == "WIDTH" && args.size() == 1) width = unsignedField(lines, args[0], "WIDTH"), have_width = true;
    else if (key == "HEIGHT" && args.size() == 1) height = unsignedField(lines, args[0], "HEIGHT");
    else if (key == "POINTS" && args.size() == 1) h.points = unsignedField(lines, args[0], "POINTS"), have_points = true;
    else if (key == "DATA" && args.size() == 1) {
      if (args[0] == "binary_compressed")
        lines.fail("DATA binary_compressed is not supported: convert with pcl_convert_pcd_ascii_binary <in> <out> 1");
      if (args[0] != "ascii" && args[0] != "binary") lines.fail("DATA must be ascii or binary");
      h.binary = args[0] == "binary";
      have_data = true;
    } else {
      lines.fail("unknown or malformed header line \"" + std::string(key.substr(0, 32)) + "\"");
    }
  }
  if (!have_data) throw DataError(file, "header", "no DATA line: not a PCD file or truncated header");
  if (h.fields.empty() || sizes.size() != h.fields.size() || types.size() != h.fields.size() ||
      (!counts.empty() && counts.size() != h.fields.size()))
    throw DataError(file, "header", "FIELDS, SIZE, TYPE (and COUNT) must list the same number of entries");
  for (std::size_t i = 0; i < h.fields.size(); ++i) {
    Field& f = h.fields[i];
    std::uint64_t size = 0, count = 1;
    if (!parseUnsigned(sizes[i], size) || (!counts.empty() && !parseUnsigned(counts[i], count)) || count == 0 ||
        count > 1024 || types[i].size() != 1)
      throw DataError(file, "header field " + f.name, "bad SIZE, TYPE or COUNT");
    f.size = int(size), f.count = int(count), f.kind = char(std::tolower(static_cast<unsigned char>(types[i][0])));
    const bool ok = f.kind == 'f' ? (size == 4 || size == 8)
                                  : (f.kind == 'i' || f.kind == 'u') && (size == 1 || size == 2 || size == 4 || size == 8);
    if (!ok) throw DataError(file, "header field " + f.name, "TYPE must be F (size 4, 8), I or U (size 1, 2, 4, 8)");
    for (int a = 0; a < 3; ++a)
      if (f.name == std::string(1, char('x' + a))) {
        if (f.count != 1) throw DataError(file, "header field " + f.name, "COUNT must be 1");
        h.xyz[a] = int(i), h.offset[a] = h.binary ? h.stride : h.columns;
      }
    h.stride += size * count;
    h.columns += count;
  }
  if (h.xyz[0] < 0 || h.xyz[1] < 0 || h.xyz[2] < 0) throw DataError(file, "header FIELDS", "needs x, y and z");
  if (!have_points) throw DataError(file, "header", "no POINTS line");
  if (have_width && (height == 0 || width > std::numeric_limits<std::uint64_t>::max() / height ||
                     width * height != h.points))
    throw DataError(file, "header", "WIDTH x HEIGHT must equal POINTS");
  h.body = lines.offset();
  h.body_line = lines.line() + 1;
  return h;
}

// PCL marks "no return" in organised clouds with x = y = z = NaN; anything else non-finite is corruption.
bool keepPoint(const double v[3], std::size_t index, std::size_t* skipped, const std::filesystem::path& file) {
  const bool all_nan = std::isnan(v[0]) && std::isnan(v[1]) && std::isnan(v[2]);
  if (all_nan) return skipped && ++*skipped, false;
  if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2]))
    throw DataError(file, "point " + std::to_string(index), "NaN or infinite coordinate (only all-NaN x y z, PCL's "
                                                            "\"no return\", is allowed and skipped)");
  return true;
}

}  // namespace

std::vector<octomap::point3d> decodePcd(std::string_view bytes, const std::filesystem::path& file,
                                        std::size_t* skipped_nan, const CloudPlacement& at) {
  const PcdHeader h = parsePcdHeader(bytes, file);
  const std::uint64_t left = bytes.size() - std::min(bytes.size(), h.body);
  std::vector<octomap::point3d> pts;
  double v[3];
  if (h.binary) {
    if (h.points > left / h.stride || h.points * h.stride != left)
      throw DataError(file, "data", "holds " + std::to_string(left) + " bytes, POINTS " + std::to_string(h.points) +
                                        " x " + std::to_string(h.stride) + " bytes expected: truncated file or wrong count");
    pts.reserve(h.points);
    for (std::uint64_t i = 0; i < h.points; ++i) {
      const char* p = bytes.data() + h.body + i * h.stride;
      for (int a = 0; a < 3; ++a) {
        const Field& f = h.fields[std::size_t(h.xyz[a])];
        v[a] = decodeScalar(p + h.offset[a], f.size, f.kind, false);
      }
      if (keepPoint(v, i, skipped_nan, file)) pts.push_back(at.place(v[0], v[1], v[2]));
    }
    return pts;
  }
  if (h.points > (left + 1) / (2 * h.columns))
    throw DataError(file, "data", "POINTS " + std::to_string(h.points) + " cannot fit in the " + std::to_string(left) +
                                      " bytes left: truncated file or wrong count");
  pts.reserve(h.points);
  TextLines lines(bytes.substr(h.body), file, h.body_line);
  std::vector<std::string_view> tok;
  for (std::uint64_t i = 0; i < h.points; ++i) {
    if (!lines.nextData(tok)) throw DataError(file, "point " + std::to_string(i), "missing: truncated file or wrong POINTS");
    if (tok.size() != h.columns)
      lines.fail("has " + std::to_string(tok.size()) + " values, the header's fields need " + std::to_string(h.columns));
    for (int a = 0; a < 3; ++a) {
      const auto t = tok[h.offset[a]];
      v[a] = (t == "nan" || t == "NaN" || t == "NAN") ? std::numeric_limits<double>::quiet_NaN()
                                                      : lines.number(t, h.offset[a], "xyz"[a] + std::string());
    }
    if (keepPoint(v, i, skipped_nan, file)) pts.push_back(at.place(v[0], v[1], v[2]));
  }
  if (lines.nextData(tok)) lines.fail("more points than POINTS says: wrong count");
  return pts;
}

}  // namespace occsweep
