// PLY (Turk 1994; the Stanford format): a text header, then ascii or binary elements in header order.
#include <cmath>
#include <string>

#include "occsweep/io/bounded_read.hpp"
#include "occsweep/data/import_cloud.hpp"
#include "occsweep/data/byte_reader.hpp"

namespace occsweep {
namespace {

struct ScalarType {
  int size = 0;
  char kind = 0;  // 'i', 'u', 'f'
};

struct Property {
  std::string name;
  ScalarType type, count_type;
  bool list = false;
};

struct Element {
  std::string name;
  std::uint64_t count = 0;
  std::vector<Property> props;
};

enum class Encoding { Ascii, Little, Big };

bool scalarType(std::string_view s, ScalarType& t) {
  static const struct { const char* name; ScalarType type; } table[] = {
      {"char", {1, 'i'}},  {"int8", {1, 'i'}},   {"uchar", {1, 'u'}},  {"uint8", {1, 'u'}},
      {"short", {2, 'i'}}, {"int16", {2, 'i'}},  {"ushort", {2, 'u'}}, {"uint16", {2, 'u'}},
      {"int", {4, 'i'}},   {"int32", {4, 'i'}},  {"uint", {4, 'u'}},   {"uint32", {4, 'u'}},
      {"float", {4, 'f'}}, {"float32", {4, 'f'}}, {"double", {8, 'f'}}, {"float64", {8, 'f'}}};
  for (const auto& e : table)
    if (s == e.name) return t = e.type, true;
  return false;
}

struct PlyHeader {
  Encoding encoding = Encoding::Ascii;
  std::vector<Element> elements;
  std::size_t body = 0;        // byte offset of the first element
  std::size_t body_line = 0;   // its line number, for ascii errors
};

PlyHeader parsePlyHeader(std::string_view bytes, const std::filesystem::path& file) {
  if (bytes.substr(0, 4) != "ply\n" && bytes.substr(0, 5) != "ply\r\n")
    throw DataError(file, "magic", "not a PLY file: must start with a line \"ply\"");
  // A header is a few hundred bytes; 1 MiB of header is a broken or hostile file (docs/robustness.md).
  constexpr std::size_t kMaxHeaderBytes = std::size_t(1) << 20;
  const auto end = bytes.substr(0, kMaxHeaderBytes + 10).find("end_header");
  if (end == std::string_view::npos && bytes.size() <= kMaxHeaderBytes)
    throw DataError(file, "header", "no end_header line: the header is not complete (truncated file?)");
  if (end == std::string_view::npos || end > kMaxHeaderBytes)
    throw DataError(file, "header", "no end_header line in the first " + std::to_string(kMaxHeaderBytes) +
                                        " bytes (1 MiB, the most a PLY header may hold)");
  const auto nl = bytes.find('\n', end);
  PlyHeader h;
  h.body = nl == std::string_view::npos ? bytes.size() : nl + 1;
  TextLines lines(bytes.substr(0, h.body), file);
  std::vector<std::string_view> tok;
  bool format_seen = false;
  while (lines.next(tok)) {
    if (tok.empty() || tok[0] == "comment" || tok[0] == "obj_info" || tok[0] == "ply") continue;
    if (tok[0] == "end_header") break;
    if (tok[0] == "format") {
      if (tok.size() != 3 || tok[2] != "1.0") lines.fail("format line must be \"format <encoding> 1.0\"");
      if (tok[1] == "ascii") h.encoding = Encoding::Ascii;
      else if (tok[1] == "binary_little_endian") h.encoding = Encoding::Little;
      else if (tok[1] == "binary_big_endian") h.encoding = Encoding::Big;
      else lines.fail("unknown format \"" + std::string(tok[1].substr(0, 32)) + "\"");
      format_seen = true;
    } else if (tok[0] == "element") {
      Element e;
      if (tok.size() != 3 || !parseUnsigned(tok[2], e.count)) lines.fail("element line must be \"element <name> <count>\"");
      e.name = std::string(tok[1]);
      h.elements.push_back(std::move(e));
    } else if (tok[0] == "property") {
      if (h.elements.empty()) lines.fail("property before any element");
      Property p;
      const bool list = tok.size() == 5 && tok[1] == "list";
      if (list ? !scalarType(tok[2], p.count_type) || !scalarType(tok[3], p.type) || p.count_type.kind == 'f'
               : tok.size() != 3 || !scalarType(tok[1], p.type))
        lines.fail("property line must be \"property <type> <name>\" or \"property list <uint type> <type> <name>\"");
      p.list = list;
      p.name = std::string(tok.back());
      h.elements.back().props.push_back(std::move(p));
    } else {
      lines.fail("unknown header keyword \"" + std::string(tok[0].substr(0, 32)) + "\"");
    }
  }
  h.body_line = lines.line() + 1;
  if (!format_seen) throw DataError(file, "header", "no format line");
  for (const auto& e : h.elements)
    if (e.props.empty() && e.count > 0)
      throw DataError(file, "header element " + e.name, "has instances but no property");
  return h;
}

// Values of the body in order, whatever the encoding; every read is bounded.
class Body {
 public:
  Body(std::string_view bytes, const PlyHeader& h, const std::filesystem::path& file)
      : enc_(h.encoding), data_(bytes.substr(h.body)), file_(file), lines_(data_, file, h.body_line) {}

  // Refuses counts that the remaining bytes cannot hold before anything is allocated.
  void checkCount(const Element& e) const {
    if (e.count == 0) return;  // an element without instances may also lack properties (found by fuzz_ply)
    std::uint64_t min = 0;
    for (const auto& p : e.props) min += std::uint64_t(p.list ? p.count_type.size : p.type.size);
    const std::uint64_t left = data_.size() - pos_;
    // ascii: every value takes at least a digit and a separator (the last line may lack its newline).
    const std::uint64_t cap = enc_ == Encoding::Ascii ? (left + 1) / (2 * e.props.size()) : left / min;
    if (e.count > cap)
      throw DataError(file_, "element " + e.name, "header claims " + std::to_string(e.count) + " instances, the " +
                                                      std::to_string(left) + " bytes left cannot hold them: truncated "
                                                      "file or wrong count");
  }
  void begin(const Element& e, std::uint64_t i) {
    where_ = e.name + " " + std::to_string(i);
    if (enc_ != Encoding::Ascii) return;
    col_ = 0;
    do {
      if (!lines_.next(tok_)) throw DataError(file_, where_, "missing: the file ends early (truncated or wrong count)");
    } while (tok_.empty());
  }
  double value(ScalarType t, const std::string& name) {
    if (enc_ == Encoding::Ascii) {
      if (col_ >= tok_.size()) lines_.fail(where_ + ": too few values, \"" + name + "\" missing");
      const double v = lines_.number(tok_[col_], col_, name);
      ++col_;
      if (t.kind != 'f' && (v != std::floor(v) || (t.kind == 'u' && v < 0)))
        lines_.fail(where_ + ": \"" + name + "\" must be an integer");
      return v;
    }
    if (std::uint64_t(t.size) > data_.size() - pos_)
      throw DataError(file_, where_ + " " + name, "the file ends early (truncated or wrong count)");
    const double v = decodeScalar(data_.data() + pos_, t.size, t.kind, enc_ == Encoding::Big);
    pos_ += std::size_t(t.size);
    return v;
  }
  void end() {
    if (enc_ == Encoding::Ascii && col_ != tok_.size()) lines_.fail(where_ + ": more values than properties");
  }
  void finish() {
    if (enc_ == Encoding::Ascii) {
      while (lines_.next(tok_))
        if (!tok_.empty()) lines_.fail("data after the last element: the header's counts are wrong");
    } else if (pos_ != data_.size()) {
      throw DataError(file_, "end", std::to_string(data_.size() - pos_) +
                                        " bytes after the last element: the header's counts are wrong");
    }
  }
  [[noreturn]] void fail(const std::string& rule) const { throw DataError(file_, where_, rule); }

 private:
  Encoding enc_;
  std::string_view data_;
  const std::filesystem::path& file_;
  TextLines lines_;
  std::vector<std::string_view> tok_;
  std::size_t col_ = 0, pos_ = 0;
  std::string where_;
};

}  // namespace

PlyData decodePly(std::string_view bytes, const std::filesystem::path& file, const CloudPlacement& at) {
  const PlyHeader h = parsePlyHeader(bytes, file);
  Body body(bytes, h, file);
  PlyData out;
  std::uint64_t vertex_count = 0;
  for (const auto& e : h.elements)
    if (e.name == "vertex") vertex_count = e.count;
  std::vector<double> values;
  std::vector<std::array<std::uint32_t, 3>> faces;
  for (const auto& e : h.elements) {
    body.checkCount(e);
    const bool vertex = e.name == "vertex", face = e.name == "face";
    int xyz[3] = {-1, -1, -1};
    for (std::size_t i = 0; i < e.props.size(); ++i)
      for (int a = 0; a < 3; ++a)
        if (!e.props[i].list && e.props[i].name == std::string(1, char('x' + a))) xyz[a] = int(i);
    if (vertex && (xyz[0] < 0 || xyz[1] < 0 || xyz[2] < 0))
      throw DataError(file, "header element vertex", "needs scalar properties x, y and z");
    if (vertex) out.vertices.reserve(e.count);
    values.resize(e.props.size());
    for (std::uint64_t i = 0; i < e.count; ++i) {
      body.begin(e, i);
      for (std::size_t pi = 0; pi < e.props.size(); ++pi) {
        const Property& p = e.props[pi];
        if (!p.list) {
          values[pi] = body.value(p.type, p.name);
          continue;
        }
        const double n = body.value(p.count_type, p.name + " count");
        const bool indices = face && (p.name == "vertex_indices" || p.name == "vertex_index");
        if (indices && n < 3) body.fail("a face needs at least 3 vertices, this one has " + std::to_string(int(n)));
        if (n < 0) body.fail("a list count must not be negative");
        std::uint32_t first = 0, prev = 0;
        for (double k = 0; k < n; ++k) {
          const double idx = body.value(p.type, p.name);
          if (!indices) continue;
          if (idx < 0 || idx >= double(vertex_count) || idx >= 4294967296.0 || idx != std::floor(idx))
            body.fail("vertex index " + std::to_string(idx) + " is outside 0.." + std::to_string(vertex_count) + "-1");
          const auto v = std::uint32_t(idx);
          if (k == 0) first = v;
          if (k >= 2) faces.push_back({first, prev, v});  // fan triangulation of a polygon
          prev = v;
        }
      }
      body.end();
      if (!vertex) continue;
      for (int a = 0; a < 3; ++a)
        if (!std::isfinite(values[std::size_t(xyz[a])])) body.fail("coordinate is NaN or infinite");
      out.vertices.push_back(
          at.place(values[std::size_t(xyz[0])], values[std::size_t(xyz[1])], values[std::size_t(xyz[2])]));
    }
  }
  body.finish();
  // Faces held vertex indices until every vertex was read (a face element may come first).
  out.triangles.reserve(faces.size());
  for (const auto& f : faces)
    out.triangles.push_back(Triangle{{out.vertices[f[0]], out.vertices[f[1]], out.vertices[f[2]]}});
  return out;
}

}  // namespace occsweep
