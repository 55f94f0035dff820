// Readers against writers over many seeds: whatever a well-formed file holds comes back exactly (docs/import.md).
#include <catch2/catch.hpp>

#include <array>
#include <bit>
#include <cstring>
#include <sstream>

#include <octomap/math/Quaternion.h>
#include <png.h>

#include "occsweep/io/bounded_read.hpp"
#include "occsweep/data/import_cloud.hpp"
#include "occsweep/data/import_depth.hpp"
#include "occsweep/data/import_intrinsics.hpp"
#include "occsweep/data/import_pose.hpp"
#include "test_helpers.hpp"

using namespace occsweep;
using octomap::point3d;

namespace {

template <class T>
void put(std::string& out, T v, bool big) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof v);
  if (big) std::reverse(b, b + sizeof v);
  out.append(b, sizeof v);
}

// A PLY with an extra property before x and after z, in one of three encodings.
std::string writePly(const std::vector<point3d>& pts, const std::vector<std::array<int, 3>>& faces, int enc) {
  static const char* names[] = {"ascii", "binary_little_endian", "binary_big_endian"};
  std::ostringstream h;
  h << "ply\nformat " << names[enc] << " 1.0\ncomment test\nelement vertex " << pts.size()
    << "\nproperty uchar red\nproperty float x\nproperty float y\nproperty float z\nproperty double nx\n";
  if (!faces.empty()) h << "element face " << faces.size() << "\nproperty list uchar int vertex_indices\n";
  h << "end_header\n";
  std::string out = h.str();
  for (const auto& p : pts) {
    if (enc == 0) {
      std::ostringstream l;
      l.precision(9);
      l << "7 " << p.x() << ' ' << p.y() << ' ' << p.z() << " 0.5\n";
      out += l.str();
    } else {
      out += char(7);
      for (int a = 0; a < 3; ++a) put(out, p(a), enc == 2);
      put(out, 0.5, enc == 2);
    }
  }
  for (const auto& f : faces) {
    if (enc == 0) out += "3 " + std::to_string(f[0]) + " " + std::to_string(f[1]) + " " + std::to_string(f[2]) + "\n";
    else {
      out += char(3);
      for (int v : f) put(out, std::int32_t(v), enc == 2);
    }
  }
  return out;
}

std::string writePcd(const std::vector<point3d>& pts, bool binary) {
  std::ostringstream h;
  h << "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z intensity\nSIZE 4 4 4 2\nTYPE F F F U\nCOUNT 1 1 1 1\nWIDTH "
    << pts.size() << "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " << pts.size() << "\nDATA "
    << (binary ? "binary" : "ascii") << "\n";
  std::string out = h.str();
  for (const auto& p : pts) {
    if (binary) {
      for (int a = 0; a < 3; ++a) put(out, p(a), false);
      put(out, std::uint16_t(42), false);
    } else {
      std::ostringstream l;
      l.precision(9);
      l << p.x() << ' ' << p.y() << ' ' << p.z() << " 42\n";
      out += l.str();
    }
  }
  return out;
}

}  // namespace

TEST_CASE("PLY ascii and binary (both endians) and PCD ascii and binary round-trip exactly over 30 seeds") {
  for (std::uint64_t seed = 1; seed <= 30; ++seed) {
    SplitMix64 rng(seed);
    const auto pts = test::randomCloud(rng, 1 + rng.next() % 300, 20.0);
    std::vector<std::array<int, 3>> faces;
    for (int f = 0; f < 20; ++f)
      faces.push_back({int(rng.next() % pts.size()), int(rng.next() % pts.size()), int(rng.next() % pts.size())});
    for (int enc = 0; enc < 3; ++enc) {
      INFO("seed " << seed << " encoding " << enc);
      const PlyData ply = decodePly(writePly(pts, faces, enc), "t.ply");
      REQUIRE(ply.vertices == pts);
      REQUIRE(ply.triangles.size() == faces.size());
      for (std::size_t f = 0; f < faces.size(); ++f)
        for (int v = 0; v < 3; ++v) REQUIRE(ply.triangles[f].v[std::size_t(v)] == pts[std::size_t(faces[f][std::size_t(v)])]);
    }
    for (bool binary : {false, true}) REQUIRE(decodePcd(writePcd(pts, binary), "t.pcd") == pts);
    std::ostringstream xyz;
    xyz.precision(9);
    xyz << "# comment\n\n";
    for (const auto& p : pts) xyz << p.x() << '\t' << p.y() << ' ' << p.z() << " 1 2\r\n";
    REQUIRE(decodeXyz(xyz.str(), "t.xyz") == pts);
  }
}

TEST_CASE("PCD: all-NaN points are skipped and counted, partly NaN points refused") {
  std::string pcd = "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 3\nHEIGHT 1\nPOINTS 3\nDATA ascii\n1 2 3\nnan nan nan\n4 5 6\n";
  std::size_t skipped = 0;
  CHECK(decodePcd(pcd, "t.pcd", &skipped) == std::vector<point3d>{{1, 2, 3}, {4, 5, 6}});
  CHECK(skipped == 1);
  pcd.replace(pcd.find("nan nan nan"), 11, "nan 0 0");
  CHECK_THROWS_WITH(decodePcd(pcd, "t.pcd"), Catch::Contains("t.pcd") && Catch::Contains("NaN"));
}

TEST_CASE("PNG (8 and 16 bit, written by libpng) and PGM (P5 8/16 bit, P2) decode exactly over 20 seeds") {
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    SplitMix64 rng(seed);
    const int w = 1 + int(rng.next() % 70), h = 1 + int(rng.next() % 50);
    const bool sixteen = seed % 2 == 0;
    DepthImage img{w, h, {}};
    for (int i = 0; i < w * h; ++i) img.values.push_back(std::uint16_t(rng.next() % (sixteen ? 65536 : 256)));
    INFO("seed " << seed << " " << w << "x" << h);
    png_image pi{};
    pi.version = PNG_IMAGE_VERSION;
    pi.width = png_uint_32(w), pi.height = png_uint_32(h);
    pi.format = sixteen ? PNG_FORMAT_LINEAR_Y : PNG_FORMAT_GRAY;
    std::vector<std::uint8_t> bytes8(img.values.begin(), img.values.end());
    const void* buffer = sixteen ? static_cast<const void*>(img.values.data()) : bytes8.data();
    png_alloc_size_t size = 0;
    REQUIRE(png_image_write_to_memory(&pi, nullptr, &size, 0, buffer, 0, nullptr));
    std::string png(size, '\0');
    REQUIRE(png_image_write_to_memory(&pi, png.data(), &size, 0, buffer, 0, nullptr));
    png.resize(size);
    CHECK(decodeDepthImage(png, "t.png").values == img.values);
    std::string p5 = "P5\n# c\n" + std::to_string(w) + " " + std::to_string(h) + "\n" + (sixteen ? "65535" : "255") + "\n";
    std::string p2 = "P2 " + std::to_string(w) + " " + std::to_string(h) + " 65535\n";
    for (auto v : img.values) {
      if (sixteen) p5 += char(v >> 8);
      p5 += char(v & 0xff);
      p2 += std::to_string(v) + (rng.next() % 2 ? "\n" : " ");
    }
    CHECK(decodeDepthImage(p5, "t.pgm").values == img.values);
    CHECK(decodeDepthImage(p2, "t.pgm").values == img.values);
  }
}

TEST_CASE("Poses: quaternion lines agree with octomath and with the same pose written as a 4x4 matrix") {
  SplitMix64 rng(7);
  for (int i = 0; i < 200; ++i) {
    double q[4], n = 0;
    for (double& v : q) v = rng.uniform() - 0.5, n += v * v;
    for (double& v : q) v /= std::sqrt(n);
    const double t[3] = {rng.uniform() * 10, rng.uniform() * 10, rng.uniform() * 10};
    std::ostringstream line;
    line.precision(17);
    line << t[0] << ' ' << t[1] << ' ' << t[2] << ' ' << q[1] << ' ' << q[2] << ' ' << q[3] << ' ' << q[0] << '\n';
    const RigidPose pose = decodePoses(line.str(), "p.txt", PoseFormat::Quaternion).at(0);
    const octomath::Quaternion oq{float(q[0]), float(q[1]), float(q[2]), float(q[3])};
    const point3d v(float(rng.uniform()), float(rng.uniform()), float(rng.uniform()));
    const point3d expected = oq.rotate(v) + point3d(float(t[0]), float(t[1]), float(t[2]));
    REQUIRE((pose.apply(v.x(), v.y(), v.z()) - expected).norm() < 1e-5f);
    std::ostringstream m;
    m.precision(17);
    for (int r = 0; r < 3; ++r)
      m << pose.rotation[std::size_t(r * 3)] << ' ' << pose.rotation[std::size_t(r * 3 + 1)] << ' '
        << pose.rotation[std::size_t(r * 3 + 2)] << ' ' << t[r] << '\n';
    m << "0 0 0 1\n";
    const RigidPose back = decodePoses(m.str(), "p.txt", PoseFormat::Matrix).at(0);
    REQUIRE(back.rotation == pose.rotation);
    REQUIRE(back.translation == pose.translation);
  }
  // Within 1e-3 of unit: normalised; beyond: refused naming the line.
  const RigidPose near = decodePoses("0 0 0 0 0 0 1.0009\n", "p.txt", PoseFormat::Quaternion).at(0);
  CHECK(near.rotation[0] == Approx(1.0).margin(1e-12));
  CHECK_THROWS_WITH(decodePoses("# h\n0 0 0 0 0 0 1.0011\n", "p.txt", PoseFormat::Quaternion),
                    Catch::Contains("p.txt: line 2") && Catch::Contains("norm"));
}

TEST_CASE("PLY: an element with no instance and no property is accepted (fuzz_ply finding: division by zero)") {
  const std::string ply = "ply\nformat ascii 1.0\nelement empty 0\nelement vertex 1\nproperty float x\n"
                          "property float y\nproperty float z\nend_header\n1 2 3\n";
  CHECK(decodePly(ply, "t.ply").vertices == std::vector<point3d>{{1, 2, 3}});
  CHECK_THROWS_WITH(decodePly("ply\nformat ascii 1.0\nelement empty 2\nend_header\n", "t.ply"),
                    Catch::Contains("no property"));
}

TEST_CASE("PCD: a header ending without a newline after DATA (fuzz_pcd finding: substr out of range)") {
  CHECK(decodePcd("FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nPOINTS 0\nDATA ascii", "t.pcd").empty());
  CHECK_THROWS_WITH(decodePcd("FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nPOINTS 1\nDATA binary", "t.pcd"),
                    Catch::Contains("truncated"));
}

TEST_CASE("Every fuzz seed of the import readers is a valid file (so that fuzzing starts deep in each reader)") {
  const auto corpus = occsweep::test::sourceTree() / "tests" / "fuzz" / "corpus";
  std::size_t seeds = 0;
  for (const auto& e : std::filesystem::recursive_directory_iterator(corpus)) {
    if (!e.is_regular_file()) continue;
    const std::string target = e.path().parent_path().filename().string();
    const std::string bytes = readFileBytes(e.path());
    INFO(e.path());
    if (target == "png" || target == "pgm") CHECK(decodeDepthImage(bytes, e.path()).values.size() > 0);
    else if (target == "ply") CHECK(decodePly(bytes, e.path()).triangles.size() == 3);
    else if (target == "pcd" || target == "xyz") CHECK(decodeCloud(bytes, e.path()).size() >= 3);
    else if (target == "pose")
      CHECK(decodePoses(std::string_view(bytes).substr(1), e.path(),
                        std::array{PoseFormat::Quaternion, PoseFormat::Matrix, PoseFormat::Tum, PoseFormat::Kitti}[bytes[0] & 3])
                .size() == 2);  // as fuzz_pose.cpp picks the format
    else if (target == "intrinsics") CHECK(decodeIntrinsics(bytes, e.path(), false).fx > 500);
    else continue;
    ++seeds;
  }
  CHECK(seeds >= 15);
  // The interlaced seed holds pixel i = 31 i (make_corpus.py; Pillow agrees): libpng's Adam7 path is used right.
  const DepthImage adam7 = readDepthImage(corpus / "png" / "gray16_adam7.png");
  REQUIRE(adam7.values.size() == 81);
  for (std::size_t i = 0; i < 81; ++i) CHECK(adam7.values[i] == i * 31);
}
