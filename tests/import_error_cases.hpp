// The bad inputs of docs/robustness.md, built in memory: what each file is, which reader takes it, and the words
// its error must contain. Shared by test_import_errors (which also prints the table with `[.table]`).
#pragma once

#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include <zlib.h>

#include "test_paths.hpp"

namespace occsweep::test {

struct BadInput {
  std::string label;   ///< the table's "input" column
  std::string kind;    ///< depth, pose, matrix, graph, cloud, truth, dataset, results
  std::string name;    ///< file name (must appear in the error)
  std::string bytes;
  std::string expect;  ///< words the error must contain
  bool write = true;   ///< false: the file is not created (missing file)
};

template <class T>
void append(std::string& s, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof v);
  s.append(b, sizeof v);
}

/// An OctoMap scan graph with one node of `pts` points (all at (1,2,3)), quaternion (w,x,y,z) and no edge.
inline std::string graph(std::uint32_t claimed, std::uint32_t pts, double qw = 1, double coord = 1.0,
                         std::int32_t tag = 3) {
  std::string s;
  append(s, std::uint32_t(1));
  append(s, claimed);
  for (std::uint32_t i = 0; i < pts; ++i) {
    append(s, tag);
    for (double v : {coord, 2.0, 3.0}) append(s, v);
  }
  append(s, std::int32_t(3));
  for (double v : {0.0, 0.0, 0.0}) append(s, v);
  append(s, std::int32_t(4));
  for (double v : {qw, 0.0, 0.0, 0.0}) append(s, v);
  append(s, std::uint32_t(0));  // id
  append(s, std::uint32_t(0));  // edges
  return s;
}

/// A PNG signature and IHDR chunk with a correct CRC, then an empty IDAT and IEND.
inline std::string pngHeader(std::uint32_t w, std::uint32_t h, std::uint8_t depth, std::uint8_t colour) {
  auto be = [](std::string& s, std::uint32_t v) {
    for (int i = 3; i >= 0; --i) s += char((v >> (8 * i)) & 0xff);
  };
  auto chunk = [&be](std::string& s, const char* type, const std::string& data) {
    be(s, std::uint32_t(data.size()));
    const std::string body = type + data;
    s += body;
    be(s, std::uint32_t(crc32(0, reinterpret_cast<const Bytef*>(body.data()), uInt(body.size()))));
  };
  std::string s = "\x89PNG\r\n\x1a\n", ihdr;
  be(ihdr, w);
  be(ihdr, h);
  ihdr += char(depth);
  ihdr += char(colour);
  ihdr += std::string(3, '\0');
  chunk(s, "IHDR", ihdr);
  chunk(s, "IDAT", "");
  chunk(s, "IEND", "");
  return s;
}

inline std::string fileBytes(const std::filesystem::path& f) {
  std::ifstream in(f, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

inline std::vector<BadInput> badInputs() {
  const std::string pgm16 = "P5 2 2 65535\n" + std::string(8, '\x01');
  const std::string ply = "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
                          "property float z\nend_header\n";
  std::string ply_nan = ply;
  for (float v : {1.f, 2.f, 3.f, std::numeric_limits<float>::quiet_NaN(), 0.f, 0.f}) append(ply_nan, v);
  const std::string pcd = "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA binary\n";
  const std::string results = fileBytes(occsweep::test::sourceTree() / "results/builtin/octomap-opt.json");
  std::string results_edited = results;
  if (auto at = results_edited.find("\"tp\""); at != std::string::npos) results_edited.replace(at, 4, "\"tq\"");
  std::string results_count = results;
  if (auto at = results_count.find("\"tp\": "); at != std::string::npos) results_count.insert(at + 6, "1");
  return {
      {"truncated PGM raster", "depth", "trunc.pgm", pgm16.substr(0, pgm16.size() - 3), "truncated"},
      {"truncated PNG stream", "depth", "trunc.png", pngHeader(4, 4, 16, 0).substr(0, 40), "corrupt PNG"},
      {"truncated scan graph", "graph", "trunc.graph", graph(3, 3).substr(0, 60), "truncated"},
      {"truncated binary PLY", "cloud", "trunc.ply", ply + std::string(13, '\0'), "cannot hold"},
      {"truncated binary PCD", "cloud", "trunc.pcd", pcd + std::string(20, '\0'), "truncated"},
      {"truncated pose matrix", "matrix", "trunc_pose.txt", "1 0 0 0\n0 1 0 0\n0 0 1 0\n", "truncated"},
      {"wrong magic: PPM (colour) as depth", "depth", "colour.pgm", "P6 1 1 255\nabc", "P5"},
      {"wrong magic: not a PLY", "cloud", "magic.ply", "plx\nformat ascii 1.0\n", "not a PLY"},
      {"wrong element tag in a graph", "graph", "tag.graph", graph(1, 1, 1, 1.0, 7), "tag"},
      {"colour PNG as depth", "depth", "rgb.png", pngHeader(4, 4, 8, 2), "greyscale"},
      {"PLY header count larger than the body", "cloud", "count.ply", ply + std::string(12, '\0'), "cannot hold"},
      {"PLY body longer than the header count", "cloud", "extra.ply", ply + std::string(36, '\0'), "after the last"},
      {"PCD WIDTH x HEIGHT != POINTS", "cloud", "wh.pcd",
       "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 3\nHEIGHT 1\nPOINTS 2\nDATA ascii\n1 2 3\n4 5 6\n", "WIDTH"},
      {"PCD binary_compressed", "cloud", "lzf.pcd",
       "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nPOINTS 2\nDATA binary_compressed\n", "not supported"},
      {"absurd size: PLY claims 10^12 vertices", "cloud", "huge.ply",
       "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000000\nproperty float x\nproperty float y\n"
       "property float z\nend_header\n" + std::string(24, '\0'), "cannot hold"},
      {"absurd size: PCD claims 10^12 points", "cloud", "huge.pcd",
       "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nPOINTS 1000000000000\nDATA ascii\n1 2 3\n", "cannot fit"},
      {"absurd size: graph node claims 4x10^9 points", "graph", "huge.graph", graph(4000000000u, 1), "truncated"},
      {"absurd size: PGM 10^6 x 10^6", "depth", "huge.pgm", "P5 1000000 1000000 65535\n\x01\x02", "pixels"},
      {"absurd size: PNG 65535 x 65535", "depth", "huge.png", pngHeader(65535, 65535, 16, 0), "pixels"},
      {"NaN in x y z text", "cloud", "nan.xyz", "1 2 3\nnan 2 3\n", "NaN"},
      {"infinity in ASCII PLY", "cloud", "inf.ply",
       "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n"
       "1 inf 3\n", "NaN and infinite"},
      {"NaN in binary PLY", "cloud", "nan.ply", ply_nan, "NaN"},
      {"NaN in a graph point", "graph", "nan.graph", graph(1, 1, 1, std::numeric_limits<double>::quiet_NaN()), "NaN"},
      {"NaN in a pose", "pose", "nan_pose.txt", "0 nan 0 0 0 0 1\n", "NaN"},
      {"non-unit quaternion (|q| = 1.5)", "pose", "quat.txt", "0 0 0 0 0 0 1.5\n", "norm"},
      {"non-unit quaternion in a graph", "graph", "quat.graph", graph(1, 1, 2.0), "unit norm"},
      {"matrix pose that is not a rotation", "matrix", "shear.txt", "1 1 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n", "rotation"},
      {"pose file with 6 columns", "pose", "cols.txt", "0 0 0 0 0 1\n", "expected 7"},
      {"pose file without a pose", "pose", "none.txt", "# only a comment\n", "no pose"},
      {"more poses than images", "pose", "two.txt", "0 0 0 0 0 0 1\n0 0 0 0 0 0 1\n", "one pose per depth image needed"},
      {"empty scan: depth image all zero", "depth", "zero.pgm", "P2 2 1 65535\n0 0\n", "empty scan"},
      {"empty scan: graph node without points", "graph", "empty.graph", graph(0, 0), "no points"},
      {"empty scan: empty x y z file", "cloud", "empty.xyz", "", "empty scan"},
      {"missing file", "cloud", "missing.xyz", "", "missing", false},
      {"a folder given as a file", "cloud", "folder.xyz", "", "folder", false},
      {"truth JSON: min > max", "truth", "boxes.json", R"([{"min":[1,0,0],"max":[0,1,1]}])", "min must be <= max"},
      {"truth JSON: not JSON", "truth", "broken.json", R"({"boxes": [)", "not valid JSON"},
      {"data-set manifest edited: a scan's point count changed", "dataset", "000000.f32", "", "truncated or wrong count",
       false},
      {"data-set manifest with a number beyond double (1e999)", "manifest", "manifest.json",
       R"({"format": "occsweep-dataset", "version": 1e999})", "not valid JSON"},
      {"results file edited by hand: a field renamed", "results", "edited_results.json", results_edited, "tp"},
      {"results file edited by hand: a TP count changed", "results", "tp_results.json", results_count, "edited by hand"},
      {"results file truncated", "results", "cut_results.json", results.substr(0, results.size() / 2), "JSON"},
  };
}

/// JSON numbers beyond double in the sweeps' grid and results loaders: found by fuzz_grid_json (nlohmann throws
/// out_of_range there, which loadGrid/readResults once let through without the file's name).
inline std::vector<BadInput> jsonOverflowInSweepsFiles() {
  return {{"grid file with a number beyond double (1e999)", "grid", "overflow_grid.json", R"({"name": 1e999})", "JSON"},
          {"results file with a number beyond double (1e999)", "results", "overflow_results.json",
           R"({"format": 1e999})", "JSON"}};
}

}  // namespace occsweep::test
