// occsweep import depth|graph|cloud|truth and mapdiff end to end on the repository's real samples (docs/import.md).
#include <catch2/catch.hpp>

#include <array>
#include <fstream>

#include "occsweep/core/voxel_filter.hpp"
#include "occsweep/data/import_dataset.hpp"
#include "occsweep/data/import_graph.hpp"
#include "occsweep/data/import_truth.hpp"
#include "occsweep/io/fnv1a.hpp"
#include "test_helpers.hpp"

using namespace occsweep;
namespace fs = std::filesystem;

namespace {
const fs::path kReal = occsweep::test::sourceTree() / "tests" / "data" / "real";
}

TEST_CASE("import commands write data sets equal to the library readers, truth is added, maps compared") {
  const fs::path dir = test::scratch("import_cli");
  const fs::path join = kReal / "slambook_joinMap";
  std::string images;
  for (int i = 1; i <= 5; ++i) images.append(" ").append((join / "depth" / (std::to_string(i) + ".pgm")).string());
  auto r = test::runCli("import depth" + images + " --poses " + (join / "pose.txt").string() +
                        " --fx 518 --fy 519 --cx 325.5 --cy 253.5 --max-depth 7 --stride 8 --out " + (dir / "join").string());
  REQUIRE(r.exit_code == 0);
  const Dataset join_set = readDataset(dir / "join");
  CHECK(join_set.scans.size() == 5);
  CHECK(join_set.source.at("truth") == "none");
  CHECK(join_set.truth.boxes.empty());
  // Every point and origin lies in the region (the bounding box), and the box is tight on some point.
  const AxisBox box = boundingBox(join_set.scans);
  for (int a = 0; a < 3; ++a) {
    CHECK(join_set.region.min[std::size_t(a)] == Approx(box.min[std::size_t(a)]));
    CHECK(join_set.region.max[std::size_t(a)] == Approx(box.max[std::size_t(a)]));
  }

  const fs::path graph = kReal / "octomap_share_data" / "spherical_scan.graph";
  r = test::runCli("import graph " + graph.string() + " --name sphere --out " + (dir / "sphere").string());
  REQUIRE(r.exit_code == 0);
  const Dataset sphere = readDataset(dir / "sphere");
  CHECK(sphere.name == "sphere");
  CHECK(sphere.scans[0].points == importScanGraph(graph).scans[0].points);

  // Truth: a JSON box and a PLY mesh (a tetrahedron), merged; then map prints confusion counts.
  std::ofstream(dir / "boxes.json") << R"({"boxes": [{"min": [-1, -1, 0], "max": [1, 1, 2]}]})";
  std::ofstream(dir / "tet.ply") << "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                                    "property float z\nelement face 4\nproperty list uchar int vertex_indices\n"
                                    "end_header\n0 0 1\n1 0 1\n0 1 1\n0 0 2\n3 0 1 2\n3 0 1 3\n3 0 2 3\n3 1 2 3\n";
  r = test::runCli("import truth " + (dir / "boxes.json").string() + " " + (dir / "tet.ply").string() +
                   " --dataset " + (dir / "join").string() + " --region -2 -2 -1 2 2 3 --out " + (dir / "join_truth").string());
  REQUIRE(r.exit_code == 0);
  const Dataset with_truth = readDataset(dir / "join_truth");
  CHECK(with_truth.truth.boxes.size() == 1);
  CHECK(with_truth.truth.mesh.size() == 4);
  CHECK(with_truth.region.min[2] == -1.0);
  CHECK(with_truth.scans.size() == join_set.scans.size());
  r = test::runCli("map --dataset " + (dir / "join_truth").string() + " --method octomap --out " + (dir / "o.ot").string());
  REQUIRE(r.exit_code == 0);
  CHECK(r.output.find("TP ") != std::string::npos);

  // mapdiff: a map against itself disagrees nowhere; OctoMap against k-NN is counted consistently.
  r = test::runCli("map --dataset " + (dir / "join").string() + " --method knn --out " + (dir / "k.ot").string());
  REQUIRE(r.exit_code == 0);
  r = test::runCli("map --dataset " + (dir / "join").string() + " --method octomap --out " + (dir / "oj.ot").string());
  REQUIRE(r.exit_code == 0);
  r = test::runCli("mapdiff " + (dir / "oj.ot").string() + " " + (dir / "oj.ot").string());
  REQUIRE(r.exit_code == 0);
  const auto self = nlohmann::json::parse(r.output.substr(r.output.find('{')));
  CHECK(self.at("disagree") == 0);
  CHECK(self.at("known_only_a") == 0);
  r = test::runCli("mapdiff " + (dir / "oj.ot").string() + " " + (dir / "k.ot").string());
  REQUIRE(r.exit_code == 0);
  const auto diff = nlohmann::json::parse(r.output.substr(r.output.find('{')));
  CHECK(diff.at("disagree").get<std::uint64_t>() ==
        diff.at("occupied_only_a").get<std::uint64_t>() + diff.at("occupied_only_b").get<std::uint64_t>());
  CHECK(diff.at("occupied_both").get<std::uint64_t>() + diff.at("occupied_only_a").get<std::uint64_t>() ==
        self.at("occupied_both").get<std::uint64_t>());  // A's occupied voxels, counted two ways
  CHECK(test::runCli("mapdiff " + (dir / "oj.ot").string() + " " + (dir / "missing.ot").string()).exit_code != 0);
}

TEST_CASE("ground truth from a PLY or PCD point cloud: the voxels holding its points") {
  const fs::path dir = test::scratch("import_truth_points");
  // Three points, two of them in one 0.1 m voxel: the truth is two voxels, whatever the format.
  std::ofstream(dir / "truth.ply") << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                      "property float z\nend_header\n0.05 0.05 0.05\n0.06 0.04 0.02\n0.35 0.05 0.15\n";
  std::ofstream(dir / "truth.pcd") << "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 3\n"
                                      "HEIGHT 1\nPOINTS 3\nDATA ascii\n0.05 0.05 0.05\n0.06 0.04 0.02\n0.35 0.05 0.15\n";
  const std::vector<octomap::point3d> expected{{0.05f, 0.05f, 0.05f}, {0.06f, 0.04f, 0.02f}, {0.35f, 0.05f, 0.15f}};
  for (const char* name : {"truth.ply", "truth.pcd"}) {
    INFO(name);
    const TruthSources t = readTruth(dir / name);
    CHECK(t.boxes.empty());
    CHECK(t.mesh.empty());
    REQUIRE(t.points.size() == expected.size());
    for (std::size_t i = 0; i < expected.size(); ++i) CHECK(t.points[i] == expected[i]);
  }

  // Through the command, onto a scan of the built-in scene: the data set keeps the points as its truth.
  REQUIRE(test::runCli("scene --out " + (dir / "scene").string()).exit_code == 0);
  for (const char* name : {"truth.ply", "truth.pcd"}) {
    INFO(name);
    const fs::path out = dir / (std::string(name) + ".set");
    const auto r = test::runCli("import truth " + (dir / name).string() + " --dataset " + (dir / "scene").string() +
                                " --region -1 -1 -1 1 1 1 --out " + out.string());
    REQUIRE(r.exit_code == 0);
    const Dataset d = readDataset(out);
    CHECK(d.truth.boxes.empty());
    CHECK(d.truth.mesh.empty());
    REQUIRE(d.truth.points.size() == expected.size());
    const GroundTruth gt = makeGroundTruth(d.truth, d.region, 0.1);
    CHECK(gt.occupied.size() == 2);
  }
}

TEST_CASE("import --voxel-filter: each scan is the voxel filter of the unfiltered import's scan, recorded in source") {
  const fs::path dir = test::scratch("import_voxel_filter");
  const fs::path join = kReal / "slambook_joinMap";
  std::string images;
  for (int i = 1; i <= 5; ++i) images.append(" ").append((join / "depth" / (std::to_string(i) + ".pgm")).string());
  // Lines of random points (several per voxel) for `import cloud`, with a shift to exercise the order: the filter
  // runs in the data set's frame, after --shift.
  std::ofstream(dir / "a.xyz") << "0.01 0.02 0.03\n0.04 0.05 0.06\n0.31 0.02 0.5\n-0.22 1.5 0.07\n-0.21 1.51 0.08\n";
  std::ofstream(dir / "b.xyz") << "1 1 1\n1.05 1.05 1.05\n1.09 1.01 1.02\n";
  const std::string depth = "import depth" + images + " --poses " + (join / "pose.txt").string() +
                            " --fx 518 --fy 519 --cx 325.5 --cy 253.5 --max-depth 7 --stride 8";
  const std::string cloud = "import cloud " + (dir / "a.xyz").string() + " " + (dir / "b.xyz").string() +
                            " --shift 0.5 -0.25 0.125";
  const std::string graph =
      "import graph " + (kReal / "octomap_share_data" / "spherical_scan.graph").string();
  for (const auto& [kind, command] : {std::pair{"depth", depth}, {"cloud", cloud}, {"graph", graph}}) {
    for (const double leaf : {0.1, 0.05}) {
      INFO(kind << " at leaf " << leaf);
      const std::string name = std::string(kind) + "-" + std::to_string(leaf);
      REQUIRE(test::runCli(command + " --out " + (dir / (name + "-raw")).string()).exit_code == 0);
      const auto r = test::runCli(command + " --voxel-filter " + std::to_string(leaf) + " --out " +
                                  (dir / (name + "-filtered")).string());
      REQUIRE(r.exit_code == 0);
      const Dataset raw = readDataset(dir / (name + "-raw")), filtered = readDataset(dir / (name + "-filtered"));
      REQUIRE(filtered.scans.size() == raw.scans.size());
      std::size_t removed = 0;
      for (std::size_t i = 0; i < raw.scans.size(); ++i) {
        CHECK(filtered.scans[i].origin == raw.scans[i].origin);
        CHECK(filtered.scans[i].points == voxelFilter(raw.scans[i].points, leaf));
        removed += raw.scans[i].points.size() - filtered.scans[i].points.size();
      }
      CHECK(removed > 0);
      CHECK(filtered.source.at("voxel_filter_leaf") == leaf);
      CHECK_FALSE(raw.source.contains("voxel_filter_leaf"));
    }
  }
  // Bad leaves: exit 2, the flag named, nothing written.
  for (const char* bad : {"0", "-0.1", "nan", "inf", "abc"}) {
    INFO("--voxel-filter " << bad);
    const fs::path out = dir / (std::string("bad-") + bad);
    const auto r = test::runCli(cloud + " --voxel-filter " + bad + " --out " + out.string());
    CHECK(r.exit_code == 2);
    CHECK(r.output.find("--voxel-filter") != std::string::npos);
    CHECK_FALSE(fs::exists(out));
  }
}

TEST_CASE("import --voxel-filter below a micrometre is refused before any file is read, naming the value and bound") {
  // Old binary: "voxelFilter: point 0 is not finite or too far out" for 1e-300, naming neither the flag nor the
  // file, once every file was read.
  const fs::path dir = test::scratch("import_voxel_leaf");
  std::ofstream(dir / "a.xyz") << "0.01 0.02 0.03\n1 1 1\n";
  for (const std::string input : {"a.xyz", "missing.xyz"})  // the leaf is refused before the file is opened
    for (const std::string leaf : {"1e-300", "1e-7"}) {
      const auto r = test::runCli("import cloud " + (dir / input).string() + " --voxel-filter " + leaf + " --out " +
                                  (dir / "out").string());
      INFO(r.output);
      CHECK(r.exit_code == 2);
      CHECK(r.output.find("--voxel-filter must be a number >= 1e-06, got " + leaf) != std::string::npos);
      CHECK_FALSE(fs::exists(dir / "out"));
    }
  const auto at_bound = test::runCli("import cloud " + (dir / "a.xyz").string() + " --voxel-filter 1e-6 --out " +
                                     (dir / "out").string());
  INFO(at_bound.output);
  CHECK(at_bound.exit_code == 0);
  CHECK(readDataset(dir / "out").scans[0].points.size() == 2);
}

namespace {

// A georeferenced coordinate (UTM-like: hundreds of km east, thousands north, a height) with centimetre digits.
std::array<double, 3> farAway(SplitMix64& rng) {
  return {std::round((1e5 + rng.uniform() * 8e5) * 100) / 100, std::round((1e6 + rng.uniform() * 8e6) * 100) / 100,
          std::round((-100 + rng.uniform() * 3000) * 100) / 100};
}

template <typename T>
void putLittle(std::ofstream& out, T v) {
  out.write(reinterpret_cast<const char*>(&v), sizeof v);  // the test machines are little-endian (x86-64, arm64)
}

void writeCloud(const fs::path& file, const std::vector<std::array<double, 3>>& pts) {
  std::ofstream out(file, std::ios::binary);
  const std::string ext = file.extension().string();
  if (ext == ".ply")
    out << "ply\nformat binary_little_endian 1.0\nelement vertex " << pts.size()
        << "\nproperty double x\nproperty double y\nproperty double z\nend_header\n";
  if (ext == ".pcd")
    out << "VERSION .7\nFIELDS x y z\nSIZE 8 8 8\nTYPE F F F\nCOUNT 1 1 1\nWIDTH " << pts.size()
        << "\nHEIGHT 1\nPOINTS " << pts.size() << "\nDATA binary\n";
  char line[128];
  for (const auto& p : pts)
    if (ext == ".xyz") {
      std::snprintf(line, sizeof line, "%.17g %.17g %.17g\n", p[0], p[1], p[2]);
      out << line;
    } else {
      for (double v : p) putLittle(out, v);
    }
}

// `x y z 0 0 0 1`: a pose line of the default format (translation, then the identity quaternion), every digit kept.
std::string identityPoseLine(const std::array<double, 3>& t) {
  char line[128];
  std::snprintf(line, sizeof line, "%.17g %.17g %.17g 0 0 0 1\n", t[0], t[1], t[2]);
  return line;
}

// ` --shift X Y Z`, every digit kept.
std::string shiftFlag(const std::array<double, 3>& shift) {
  char text[128];
  std::snprintf(text, sizeof text, " --shift %.17g %.17g %.17g", shift[0], shift[1], shift[2]);
  return text;
}

}  // namespace

// docs/import.md, "Far-away (georeferenced) clouds": the shift (and the pose) are added in double before the one
// rounding to float32, so that the centimetres of a UTM coordinate survive. Oracle: float(double(x) + shift), per
// seed, for text, double PLY and double PCD, and for a pose whose translation is the far-away part.
TEST_CASE("import cloud --shift: every stored coordinate is float(double(x) + shift), in every reader") {
  const fs::path dir = test::scratch("import_shift_exact");
  constexpr int kSeeds = 24, kPoints = 40;
  for (const std::string ext : {".xyz", ".ply", ".pcd", "-posed.xyz"}) {
    INFO("format " << ext);
    const bool posed = ext == "-posed.xyz";
    std::vector<std::vector<std::array<double, 3>>> expected;
    std::string files, poses;
    std::array<double, 3> shift{};
    for (int seed = 1; seed <= kSeeds; ++seed) {
      SplitMix64 rng(std::uint64_t(seed) * 7919);
      const auto base = farAway(rng);
      if (seed == 1) shift = {-std::floor(base[0]), -std::floor(base[1]), -std::floor(base[2])};
      std::vector<std::array<double, 3>> in, want;
      for (int i = 0; i < kPoints; ++i) {
        std::array<double, 3> p{}, w{};
        for (std::size_t a = 0; a < 3; ++a) {
          const double local = std::round((rng.uniform() - 0.5) * 100 * 100) / 100;  // within 50 m, centimetres
          p[a] = posed ? local : base[a] + local;
          w[a] = (posed ? (local + base[a]) : p[a]) + shift[a];  // identity rotation: R p + t = p + t exactly
        }
        in.push_back(p);
        want.push_back(w);
      }
      fs::path file = dir / "c";
      file += std::to_string(seed);
      file += posed ? std::string(".xyz") : ext;
      writeCloud(file, in);
      files.append(" ").append(file.string());
      poses += identityPoseLine(base);
      expected.push_back(want);
    }
    std::ofstream(dir / "poses.txt") << poses;
    const std::string shift_text = shiftFlag(shift);
    const fs::path out = dir / ("ds" + ext);
    const auto r = test::runCli("import cloud" + files + shift_text +
                                (posed ? " --poses " + (dir / "poses.txt").string() : std::string()) + " --out " +
                                out.string());
    REQUIRE(r.exit_code == 0);
    const Dataset d = readDataset(out);
    REQUIRE(d.scans.size() == expected.size());
    std::size_t wrong = 0;
    for (std::size_t s = 0; s < expected.size(); ++s) {
      REQUIRE(d.scans[s].points.size() == expected[s].size());
      for (std::size_t i = 0; i < expected[s].size(); ++i)
        for (std::size_t a = 0; a < 3; ++a)
          if (d.scans[s].points[i](unsigned(a)) != float(expected[s][i][a])) ++wrong;
    }
    CHECK(wrong == 0);
  }
  // docs/import.md's example: 500000.01 4000000.02 10.03 shifted by -500000 -4000000 -10 is 0.01 0.02 0.03.
  std::ofstream(dir / "one.xyz") << "500000.01 4000000.02 10.03\n";
  REQUIRE(test::runCli("import cloud " + (dir / "one.xyz").string() + " --shift -500000 -4000000 -10 --out " +
                       (dir / "one").string()).exit_code == 0);
  const auto p = readDataset(dir / "one").scans.at(0).points.at(0);
  CHECK(p.x() == float(500000.01 - 500000));
  CHECK(p.y() == float(4000000.02 - 4000000));
  CHECK(p.z() == float(10.03 - 10));
}

// The truth of a shifted data set is shifted the same way: in double, then rounded once (docs/import.md). Old binary:
// the truth's points were rounded to float32 before the shift (500000.01 became 0, not 0.01).
TEST_CASE("import truth onto a shifted data set: every truth coordinate is float(double(x) + shift)") {
  const fs::path dir = test::scratch("import_truth_shift_exact");
  std::ofstream(dir / "one.xyz") << "500000.01 4000000.02 10.03\n500001 4000001 11\n";
  REQUIRE(test::runCli("import cloud " + (dir / "one.xyz").string() + " --shift -500000 -4000000 -10 --out " +
                       (dir / "ds").string()).exit_code == 0);
  std::vector<std::array<double, 3>> truth;
  SplitMix64 rng(31);
  for (int i = 0; i < 60; ++i)
    truth.push_back({500000 + std::round(rng.uniform() * 10000) / 100, 4000000 + std::round(rng.uniform() * 10000) / 100,
                     10 + std::round(rng.uniform() * 300) / 100});
  for (const std::string ext : {".ply", ".pcd"}) {
    INFO(ext);
    writeCloud(dir / ("truth" + ext), truth);
    const auto r = test::runCli("import truth " + (dir / ("truth" + ext)).string() + " --dataset " + (dir / "ds").string() +
                                " --out " + (dir / ("with" + ext)).string());
    INFO(r.output);
    REQUIRE(r.exit_code == 0);
    const Dataset d = readDataset(dir / ("with" + ext));
    REQUIRE(d.truth.points.size() == truth.size());
    std::size_t wrong = 0;
    const std::array<double, 3> shift{-500000, -4000000, -10};
    for (std::size_t i = 0; i < truth.size(); ++i)
      for (std::size_t a = 0; a < 3; ++a)
        if (d.truth.points[i](unsigned(a)) != float(truth[i][a] + shift[a])) ++wrong;
    CHECK(wrong == 0);
  }
}

// docs/import.md: the region a far-away import reports is its real size, and the reason map and sweep refuse it is
// the key range, not the region-voxel limit (a 1,000-voxel region was reported "more than the limit of 67108864").
TEST_CASE("import reports a far-away region's own voxel count and the key range, not the voxel limit") {
  const fs::path dir = test::scratch("import_far_region");
  std::ofstream(dir / "far.xyz") << "5000 0 0\n5001 1 1\n";
  const auto r = test::runCli("import cloud " + (dir / "far.xyz").string() + " --origin 5000 0 0 --out " +
                              (dir / "far").string());
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK(r.output.find("1000 voxels at 0.1 m, outside OctoMap's key range [-3276.8, 3276.8)") != std::string::npos);
  CHECK(r.output.find("more than the limit") == std::string::npos);
}

// The same for depth images: back-projected in double, moved by a far-away pose and --shift, rounded once.
TEST_CASE("import depth --shift: every stored coordinate is float(pose(x) + shift), rounded once") {
  const fs::path dir = test::scratch("import_depth_shift_exact");
  constexpr int kW = 6, kH = 5, kFrames = 12;
  const double fx = 5, fy = 6, cx = 2.5, cy = 2, scale = 1000;
  std::string images, poses;
  std::vector<std::vector<std::array<double, 3>>> expected;
  std::array<double, 3> shift{};
  for (int f = 0; f < kFrames; ++f) {
    SplitMix64 rng(std::uint64_t(f) * 104729 + 3);
    const auto t = farAway(rng);
    if (f == 0) shift = {-std::floor(t[0]), -std::floor(t[1]), -std::floor(t[2])};
    std::string body;
    std::vector<std::array<double, 3>> want;
    for (int v = 0; v < kH; ++v)
      for (int u = 0; u < kW; ++u) {
        const auto raw = std::uint16_t(500 + rng.next() % 20000);
        body += char(raw >> 8), body += char(raw & 0xff);  // PGM: 16-bit big-endian
        const double z = raw / scale, x = (double(u) - cx) * z / fx, y = (double(v) - cy) * z / fy;
        want.push_back({(x + t[0]) + shift[0], (y + t[1]) + shift[1], (z + t[2]) + shift[2]});  // identity rotation
      }
    fs::path image = dir / "d";
    image += std::to_string(f);
    image += ".pgm";
    std::ofstream(image, std::ios::binary) << "P5\n" << kW << ' ' << kH << "\n65535\n" << body;
    images.append(" ").append(image.string());
    poses += identityPoseLine(t);
    expected.push_back(want);
  }
  std::ofstream(dir / "poses.txt") << poses;
  const std::string shift_text = shiftFlag(shift);
  const auto r = test::runCli("import depth" + images + " --poses " + (dir / "poses.txt").string() +
                              " --fx 5 --fy 6 --cx 2.5 --cy 2" + shift_text + " --out " + (dir / "ds").string());
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const Dataset d = readDataset(dir / "ds");
  REQUIRE(d.scans.size() == expected.size());
  std::size_t wrong = 0;
  for (std::size_t s = 0; s < expected.size(); ++s) {
    REQUIRE(d.scans[s].points.size() == expected[s].size());
    for (std::size_t i = 0; i < expected[s].size(); ++i)
      for (std::size_t a = 0; a < 3; ++a)
        if (d.scans[s].points[i](unsigned(a)) != float(expected[s][i][a])) ++wrong;
  }
  CHECK(wrong == 0);
}

namespace {

// Two maps of each method: twenty sweeps take seconds, and compare's statistics run as on any grid.
void writeSmallGrids(const fs::path& dir) {
  std::ofstream(dir / "octomap-small.json")
      << R"({"name": "octomap-small", "method": "octomap", "parameters": {"p_max": {"value": 0.98},
      "p_min": {"value": 0.02}, "p_h": {"min": 0.7, "max": 0.82, "step": 0.12}, "p_m": {"value": 0.4}, "p_t": {"step": 0.12}}})";
  std::ofstream(dir / "knn-small.json")
      << R"({"name": "knn-small", "method": "knn", "parameters": {"p_max": {"value": 0.98}, "p_min": {"value": 0.02},
      "p_m": {"value": 0.26}, "p_m_out": {"value": 0.26}, "p_u": {"min": 0.62, "max": 0.74, "step": 0.12},
      "p_l": {"value": 0.5}, "p_t": {"step": 0.12}, "k": [1]}})";
}

// Each data set swept with both small grids; the results files, for compare's command line.
std::string sweptResults(const fs::path& dir, const std::vector<fs::path>& datasets) {
  std::string files;
  for (const fs::path& d : datasets)
    for (const char* grid : {"octomap-small", "knn-small"}) {
      // Built with append: g++ 12 warns wrongly (-Wrestrict) on some chains of string operator+.
      const fs::path out = dir / d.filename().string().append("-").append(grid).append(".json");
      const fs::path grid_file = dir / std::string(grid).append(".json");
      const auto r = test::runCli(std::string("sweep --dataset ").append(d.string()).append(" --grid ")
                                      .append(grid_file.string()).append(" --threads 1 --out ").append(out.string()));
      REQUIRE(r.exit_code == 0);
      files.append(" ").append(out.string());
    }
  return files;
}

// Points of a 1 m box's faces seen from `sensor` (identity rotation: sensor frame = world frame minus `sensor`),
// with noise and outliers of seed `seed`: one SGBM setting's cloud of one view.
void writeBoxView(const fs::path& file, const std::array<double, 3>& sensor, std::uint64_t seed) {
  SplitMix64 rng(seed);
  std::ofstream out(file);
  for (int i = 0; i < 600; ++i) {
    const double u = rng.uniform() - 0.5, z = rng.uniform(), noise = (rng.uniform() - 0.5) * 0.06;
    const double x = sensor[0] > 0 ? 0.5 + noise : -0.5 + noise;  // the face towards the sensor
    const double towards_sensor = rng.uniform() < 0.1 ? rng.uniform() * 0.5 : 0.0;  // an outlier in free space
    out << x + (sensor[0] - x) * towards_sensor - sensor[0] << ' ' << u - sensor[1] << ' ' << z - sensor[2] << '\n';
  }
}

// Two views of the box (the clouds of setting `n`), and `blank` (a third cloud, with --skip-empty) if given, imported
// with `poses`, then `truth` added: the data set `out`.
fs::path importBoxViews(const fs::path& dir, std::size_t n, const fs::path& poses, const fs::path& truth,
                        const std::string& out, const std::string& blank = "") {
  const std::string a = (dir / ("a" + std::to_string(n) + ".xyz")).string();
  const std::string b = (dir / ("b" + std::to_string(n) + ".xyz")).string();
  writeBoxView(a, {3, 0, 0}, 100 + n);
  writeBoxView(b, {-3, 0, 0}, 200 + n);
  const fs::path scans = dir / (out + "-scans");
  const std::string more = blank.empty() ? "" : " " + blank + " --skip-empty";
  REQUIRE(test::runCli("import cloud " + a + " " + b + more + " --poses " + poses.string() + " --out " + scans.string())
              .exit_code == 0);
  REQUIRE(test::runCli("import truth " + truth.string() + " --dataset " + scans.string() + " --out " +
                       (dir / out).string())
              .exit_code == 0);
  return dir / out;
}

// slambook_joinMap's depth frames, a pose line each in `poses`, imported with --skip-empty, then the truth `box` added
// in `region`: the data set `out`; what import depth printed.
std::string importDepthRoom(const fs::path& dir, const std::vector<fs::path>& frames, const fs::path& poses,
                            const fs::path& box, const std::string& region, const std::string& out) {
  std::string files;
  for (const fs::path& frame : frames) files.append(" ").append(frame.string());
  const fs::path scans = dir / (out + "-scans");
  const auto r = test::runCli("import depth" + files + " --poses " + poses.string() + " --skip-empty --fx 518 --fy 519 "
                              "--cx 325.5 --cy 253.5 --max-depth 7 --stride 8 --out " + scans.string());
  REQUIRE(r.exit_code == 0);
  REQUIRE(test::runCli("import truth " + box.string() + " --dataset " + scans.string() + " --region " + region +
                       " --out " + (dir / out).string())
              .exit_code == 0);
  return r.output;
}

// Lines `first` ... `first + count - 1` of slambook_joinMap's pose file (counting from 0) into `file`.
void writePoseLines(const fs::path& file, std::size_t first, std::size_t count) {
  std::ifstream in(kReal / "slambook_joinMap" / "pose.txt");
  std::ofstream out(file);
  std::string line;
  for (std::size_t i = 0; i < first + count && std::getline(in, line); ++i)
    if (i >= first) out << line << '\n';
}

fs::path depthFrame(int number) {
  return kReal / "slambook_joinMap" / "depth" / std::to_string(number).append(".pgm");
}

}  // namespace

TEST_CASE("ten SGBM settings of one pair (one truth, one pose file, default names) are one scene in compare") {
  const fs::path dir = test::scratch("import_units_settings");
  writeSmallGrids(dir);
  std::ofstream(dir / "poses.txt") << "3 0 0 0 0 0 1\n-3 0 0 0 0 0 1\n";
  std::ofstream(dir / "box.json") << R"({"boxes": [{"min": [-0.5, -0.5, 0], "max": [0.5, 0.5, 1]}]})";
  std::vector<fs::path> datasets;
  for (std::size_t setting = 0; setting < 10; ++setting)
    datasets.push_back(importBoxViews(dir, setting, dir / "poses.txt", dir / "box.json",
                                      "setting" + std::to_string(setting)));
  const std::string files = sweptResults(dir, datasets);
  const auto r = test::runCli("compare" + files + " --json " + (dir / "units.json").string());
  REQUIRE(r.exit_code == 0);
  const std::string out = test::joinedLines(r.output);
  // The old binary: "knn, optima: ...: n = 10 data sets; ...", as if the ten settings were ten recordings.
  CHECK(out.find("n = 10 data sets") == std::string::npos);
  CHECK(out.find("10 data sets over 1 scene") != std::string::npos);
  CHECK(out.find("too few scenes to tell (n = 1") != std::string::npos);
  const auto knn = nlohmann::json::parse(test::bytesOf(dir / "units.json")).at("statistics").at(1);
  CHECK(knn.at("datasets") == 10);
  CHECK(knn.at("scenes") == 1);
  CHECK(knn.at("optima_over_datasets").at("per_dataset").size() == 1);

  // Declared otherwise, each name is a unit, and every verdict names the declaration.
  const auto named = test::runCli("compare" + files + " --units names");
  REQUIRE(named.exit_code == 0);
  const std::string named_out = test::joinedLines(named.output);
  CHECK(named_out.find("n = 10 data sets") != std::string::npos);
  CHECK(named_out.find("units declared by --units names") != std::string::npos);
}

TEST_CASE("six cuts of four depth frames of one room are one scene, joined by the frames they share") {
  const fs::path dir = test::scratch("import_units_cuts");
  writeSmallGrids(dir);
  const fs::path join = kReal / "slambook_joinMap";
  // Every pair of frames 1-4, each with a truth of its own (boxes 2.00 to 2.05 m high): only the frames join them.
  const std::vector<std::array<int, 2>> cuts = {{1, 2}, {2, 3}, {3, 4}, {1, 3}, {2, 4}, {1, 4}};
  std::vector<fs::path> datasets;
  for (std::size_t c = 0; c < cuts.size(); ++c) {
    const auto [first, second] = cuts[c];
    const std::string n = std::to_string(c);
    auto frame = [&join](int i) { return (join / "depth" / std::to_string(i).append(".pgm")).string(); };
    const std::string frames = std::string(" ").append(frame(first)).append(" ").append(frame(second));
    REQUIRE(test::runCli("import depth" + frames + " --poses " + (join / "pose.txt").string() + " --pose-start " +
                         std::to_string(first - 1) + " --pose-step " + std::to_string(second - first) +
                         " --fx 518 --fy 519 --cx 325.5 --cy 253.5 --max-depth 7 --stride 8 --out " +
                         (dir / ("frames" + n)).string())
                .exit_code == 0);
    std::ofstream(dir / ("box" + n + ".json")) << R"({"boxes": [{"min": [-1, -1, 0], "max": [1, 1, 2.0)" << n << "]}]}";
    datasets.push_back(dir / ("cut" + n));
    REQUIRE(test::runCli("import truth " + (dir / ("box" + n + ".json")).string() + " --dataset " +
                         (dir / ("frames" + n)).string() + " --region -2 -2 -1 2 2 3 --out " + datasets.back().string())
                .exit_code == 0);
  }
  const auto r = test::runCli("compare" + sweptResults(dir, datasets));
  REQUIRE(r.exit_code == 0);
  const std::string out = test::joinedLines(r.output);
  CHECK(out.find("n = 6 data sets") == std::string::npos);  // the old binary's sample
  CHECK(out.find("6 data sets over 1 scene") != std::string::npos);
  CHECK(out.find("too few scenes to tell (n = 1") != std::string::npos);
}

TEST_CASE("built-in scenes of one room with other scan counts are one scene in compare") {
  // The same boxes and region, 4 to 7 scans (scan 0 the same in all): one room, not four (docs/statistics.md rule 1).
  const fs::path dir = test::scratch("scene_units_scans");
  writeSmallGrids(dir);
  std::vector<fs::path> datasets;
  for (int scans = 4; scans <= 7; ++scans) {
    datasets.push_back(dir / std::string("n").append(std::to_string(scans)));
    REQUIRE(test::runCli("scene --width 32 --height 24 --scans " + std::to_string(scans) + " --out " +
                         datasets.back().string())
                .exit_code == 0);
  }
  const auto r = test::runCli("compare" + sweptResults(dir, datasets));
  REQUIRE(r.exit_code == 0);
  const std::string out = test::joinedLines(r.output);
  CHECK(out.find("over 4 scenes") == std::string::npos);  // the old binary: "4 (4 over 4 scenes)", "n = 4 scenes"
  CHECK(out.find("4 (1 over 1 scene)") != std::string::npos);  // four sets, all named builtin-O, of one scene
  CHECK(out.find("1 data set over 1 scene") != std::string::npos);
  CHECK(out.find("too few scenes to tell (n = 1") != std::string::npos);
}

TEST_CASE("one recording's pose and truth files copied with a comment or CRLF line ends are one scene in compare") {
  const fs::path dir = test::scratch("import_units_line_ends");
  writeSmallGrids(dir);
  const std::vector<std::string> poses = {"3 0 0 0 0 0 1\n-3 0 0 0 0 0 1\n", "# copied\n3 0 0 0 0 0 1\n-3 0 0 0 0 0 1\n",
                                          "3 0 0 0 0 0 1\r\n-3 0 0 0 0 0 1\r\n"};
  const std::vector<std::string> truth = {R"({"boxes": [{"min": [-0.5, -0.5, 0], "max": [0.5, 0.5, 1]}]})",
                                          "{\"boxes\": [{\"min\": [-0.5, -0.5, 0], \"max\": [0.5, 0.5, 1]}]}\n",
                                          "{\"boxes\":\r\n [{\"min\": [-0.5, -0.5, 0.0], \"max\": [0.5, 0.5, 1.0]}]}\r\n"};
  std::vector<fs::path> datasets;
  for (std::size_t copy = 0; copy < poses.size(); ++copy) {
    const std::string n = std::to_string(copy);
    std::ofstream(dir / ("poses" + n + ".txt"), std::ios::binary) << poses[copy];
    std::ofstream(dir / ("box" + n + ".json"), std::ios::binary) << truth[copy];
    datasets.push_back(importBoxViews(dir, copy, dir / ("poses" + n + ".txt"), dir / ("box" + n + ".json"), "copy" + n));
  }
  const auto r = test::runCli("compare" + sweptResults(dir, datasets));
  REQUIRE(r.exit_code == 0);
  const std::string out = test::joinedLines(r.output);
  CHECK(out.find("over 3 scenes") == std::string::npos);  // the old binary: each copy a recording of its own
  CHECK(out.find("3 data sets over 1 scene") != std::string::npos);
}

TEST_CASE("one recording re-written (CRLF clouds, a commented pose file, its own truth) is one scene in compare") {
  // Only the points read join the copies: their input and pose files differ in bytes, their truths and regions too.
  const fs::path dir = test::scratch("import_units_rewritten");
  writeSmallGrids(dir);
  std::ofstream(dir / "poses0.txt") << "3 0 0 0 0 0 1\n-3 0 0 0 0 0 1\n";
  std::ofstream(dir / "poses1.txt") << "# the same poses\n3 0 0 0 0 0 1\n-3 0 0 0 0 0 1\n";
  std::ofstream(dir / "box0.json") << R"({"boxes": [{"min": [-0.5, -0.5, 0], "max": [0.5, 0.5, 1]}]})";
  std::ofstream(dir / "box1.json") << R"({"boxes": [{"min": [-0.5, -0.5, 0], "max": [0.5, 0.5, 1.05]}]})";
  std::vector<fs::path> datasets = {importBoxViews(dir, 0, dir / "poses0.txt", dir / "box0.json", "copy0")};
  for (const char* view : {"a", "b"}) {  // the clouds of copy0 with CRLF line ends: other bytes, the same points
    std::string text = test::bytesOf(dir / std::string(view).append("0.xyz")), crlf;
    for (char c : text) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
    std::ofstream(dir / std::string(view).append("1.xyz"), std::ios::binary) << crlf;
  }
  const fs::path scans = dir / "copy1-scans";
  REQUIRE(test::runCli("import cloud " + (dir / "a1.xyz").string() + " " + (dir / "b1.xyz").string() + " --poses " +
                       (dir / "poses1.txt").string() + " --out " + scans.string())
              .exit_code == 0);
  datasets.push_back(dir / "copy1");
  REQUIRE(test::runCli("import truth " + (dir / "box1.json").string() + " --dataset " + scans.string() + " --out " +
                       datasets.back().string())
              .exit_code == 0);
  const auto r = test::runCli("compare" + sweptResults(dir, datasets));
  REQUIRE(r.exit_code == 0);
  const std::string out = test::joinedLines(r.output);
  CHECK(out.find("over 2 scenes") == std::string::npos);  // the old binary: "2 data sets over 2 scenes"
  CHECK(out.find("2 data sets over 1 scene") != std::string::npos);
}

TEST_CASE("two cuts of one room with pose files and regions of their own and one truth are one scene in compare") {
  // Frames 1-2 and 3-4, each cut with its own pose file and --region, one truth: only the truth joins them.
  const fs::path dir = test::scratch("import_units_one_truth");
  writeSmallGrids(dir);
  std::ofstream(dir / "box.json") << R"({"boxes": [{"min": [-1, -1, 0], "max": [1, 1, 2]}]})";
  const std::array<std::string, 2> regions = {"-2 -2 -1 2 2 3", "-3 -3 -1 3 3 3"};
  std::vector<fs::path> datasets;
  for (int cut = 0; cut < 2; ++cut) {
    const std::string n = std::to_string(cut);
    writePoseLines(dir / ("poses" + n + ".txt"), std::size_t(2 * cut), 2);
    importDepthRoom(dir, {depthFrame(2 * cut + 1), depthFrame(2 * cut + 2)}, dir / ("poses" + n + ".txt"),
                    dir / "box.json", regions[std::size_t(cut)], "cut" + n);
    datasets.push_back(dir / ("cut" + n));
  }
  const auto r = test::runCli("compare" + sweptResults(dir, datasets) + " --json " + (dir / "units.json").string());
  REQUIRE(r.exit_code == 0);
  const std::string out = test::joinedLines(r.output);
  CHECK(out.find("over 2 scenes") == std::string::npos);  // the old binary: "2 data sets over 2 scenes"
  CHECK(out.find("2 data sets over 1 scene") != std::string::npos);
  const auto knn = nlohmann::json::parse(test::bytesOf(dir / "units.json")).at("statistics").at(1);
  CHECK(knn.at("scenes") == 1);
  CHECK(knn.at("optima_over_datasets").at("sample") ==
        "2 data sets over 1 scene (scenes by content hashes: data sets sharing an input file, the points read, the "
        "truth, or a generated scene are one)");
}

TEST_CASE("recordings sharing only a blank frame --skip-empty dropped are scenes of their own in compare") {
  // Two depth recordings and two cloud recordings, each with its own frames, poses and truth, and the same blank
  // frame (an all-zero PGM, an empty cloud file) among its frames: what they keep shares nothing.
  const fs::path dir = test::scratch("import_units_blank_frame");
  writeSmallGrids(dir);
  const std::string blank_pgm = std::string("P5 4 4 65535\n").append(32, '\0');
  std::ofstream(dir / "blank.pgm", std::ios::binary) << blank_pgm;
  std::ofstream(dir / "blank.xyz");
  std::vector<fs::path> datasets;
  for (int room = 0; room < 2; ++room) {
    const std::string n = std::to_string(room);
    std::ofstream(dir / ("box" + n + ".json"))
        << R"({"boxes": [{"min": [-1, -1, 0], "max": [1, 1, 2.0)" << n << "]}]}";
    writePoseLines(dir / ("depth-poses" + n + ".txt"), std::size_t(2 * room), 3);
    const std::vector<fs::path> frames = {depthFrame(2 * room + 1), depthFrame(2 * room + 2), dir / "blank.pgm"};
    const std::string said = importDepthRoom(dir, frames, dir / ("depth-poses" + n + ".txt"),
                                             dir / ("box" + n + ".json"), "-2 -2 -1 2 2 3", "depth" + n);
    CHECK(said.find("--skip-empty: dropped 1 of 3 frames without a valid point (the first: " +
                    (dir / "blank.pgm").string() + ")") != std::string::npos);
    datasets.push_back(dir / ("depth" + n));
    const auto source = readDataset(datasets.back()).source;
    CHECK(source.at("frames_dropped_empty") == nlohmann::json::array({2}));
    nlohmann::json kept = nlohmann::json::array();
    for (const fs::path& frame : {frames[0], frames[1]}) {
      Fnv1a bytes;
      bytes.feed(test::bytesOf(frame));
      kept.push_back(bytes.hex());
    }
    CHECK(source.at("provenance").at("inputs") == kept);  // the old binary: the blank frame's hash too
    // The same with clouds, whose blank frame is an empty file.
    std::ofstream(dir / ("cloud-poses" + n + ".txt"))
        << (room == 0 ? "3 0 0 0 0 0 1\n-3 0 0 0 0 0 1\n0 0 5 0 0 0 1\n"
                      : "3 0 0.1 0 0 0 1\n-3 0 0.1 0 0 0 1\n0 0 6 0 0 0 1\n");
    std::ofstream(dir / ("cloud-box" + n + ".json"))
        << R"({"boxes": [{"min": [-0.5, -0.5, 0], "max": [0.5, 0.5, 1.0)" << n << "]}]}";
    datasets.push_back(importBoxViews(dir, std::size_t(room), dir / ("cloud-poses" + n + ".txt"),
                                      dir / ("cloud-box" + n + ".json"), "cloud" + n, (dir / "blank.xyz").string()));
    CHECK(readDataset(datasets.back()).source.at("provenance").at("inputs").size() == 2);
  }
  const auto r = test::runCli("compare" + sweptResults(dir, datasets));
  REQUIRE(r.exit_code == 0);
  const std::string out = test::joinedLines(r.output);
  CHECK(out.find("over 2 scenes") == std::string::npos);  // the old binary: each pair joined by its blank frame
  CHECK(out.find("4 data sets over 4 scenes") != std::string::npos);
}

TEST_CASE("a malformed provenance in a manifest or a results file is refused, naming the file and the field") {
  const fs::path dir = test::scratch("provenance_malformed");
  writeSmallGrids(dir);
  REQUIRE(test::runCli("scene --width 32 --height 24 --scans 4 --out " + (dir / "good").string()).exit_code == 0);
  const std::string results = sweptResults(dir, {dir / "good"});
  const fs::path manifest = dir / "good" / "manifest.json";
  const auto good = nlohmann::json::parse(test::bytesOf(manifest));
  const std::vector<std::pair<nlohmann::json, std::string>> bad = {
      {5, "source.provenance: must be an object of content hashes"},
      {{{"scene", "zz"}}, "source.provenance.scene: must be a content hash, 16 lowercase hex digits"},
      {{{"inputs", "abc"}}, "source.provenance.inputs: must be an array of content hashes"},
      {{{"scene", "ABCDEF0123456789"}}, "source.provenance.scene: must be a content hash"},
      {{{"input", {"abcdef0123456789"}}}, "source.provenance.input: is not a provenance field"}};
  for (const auto& [provenance, message] : bad) {
    INFO(provenance.dump());
    nlohmann::json edited = good;
    edited["source"]["provenance"] = provenance;
    std::ofstream(manifest) << edited.dump();
    const fs::path out = dir / "bad.json";
    const auto r = test::runCli("sweep --dataset " + (dir / "good").string() + " --grid " +
                                (dir / "octomap-small.json").string() + " --out " + out.string());
    CHECK(r.exit_code == 2);  // the old binary: 0, the value read as "no hashes"
    CHECK(r.output.find(manifest.string() + ": " + message) != std::string::npos);
    CHECK(r.output.find("remove it") != std::string::npos);
    CHECK(!fs::exists(out));
  }
  // The same in a results file, where compare reads it.
  const fs::path results_file = dir / "good-octomap-small.json";
  auto edited = nlohmann::json::parse(test::bytesOf(results_file));
  edited["dataset"]["point_cloud_set"]["provenance"] = {{"scene", "zz"}};
  std::ofstream(results_file) << edited.dump();
  const auto r = test::runCli("compare" + results);
  CHECK(r.exit_code == 2);
  CHECK(r.output.find(results_file.string() + ": dataset.point_cloud_set.provenance.scene: must be a content hash") !=
        std::string::npos);
}

TEST_CASE("import records the content hashes of its inputs, poses, truth and region in source.provenance") {
  const fs::path dir = test::scratch("import_provenance");
  std::ofstream(dir / "a.xyz") << "1 0 0\n";
  std::ofstream(dir / "b.xyz") << "2 0 0\n";
  std::ofstream(dir / "box.json") << R"({"boxes": [{"min": [0, -1, -1], "max": [3, 1, 1]}]})";
  auto provenanceOf = [&](const std::string& args, const std::string& out) {
    REQUIRE(test::runCli("import cloud " + args + " --out " + (dir / out).string()).exit_code == 0);
    REQUIRE(test::runCli("import truth " + (dir / "box.json").string() + " --dataset " + (dir / out).string() +
                         " --out " + (dir / (out + "-truth")).string())
                .exit_code == 0);
    return readDataset(dir / (out + "-truth")).source.at("provenance");
  };
  const auto a = provenanceOf((dir / "a.xyz").string(), "a"), b = provenanceOf((dir / "b.xyz").string(), "b");
  const auto moved = provenanceOf((dir / "b.xyz").string() + " --origin 0 0 1", "moved");
  Fnv1a bytes;
  bytes.feed("1 0 0\n");
  CHECK(a.at("inputs") == nlohmann::json::array({bytes.hex()}));  // the file's bytes, FNV-1a 64
  CHECK(a.at("inputs") != b.at("inputs"));
  CHECK(a.at("truth") == b.at("truth"));
  CHECK(a.at("region") == b.at("region"));
  CHECK(a.at("poses") == b.at("poses"));  // world-frame clouds from one origin: one recording's placement
  CHECK(moved.at("poses") != b.at("poses"));
}
