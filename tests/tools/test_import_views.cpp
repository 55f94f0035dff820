// The views `occsweep import` records (docs/import.md, "Sensor views") and what observable truth makes of them
// (docs/results-format.md, "Truth"), through the command alone, so that OCCSWEEP_TEST_CLI can run them on a build
// from before views: a depth camera facing a wall, a range sensor's cone, data sets without views, the built-in
// scene, and the slambook joinMap frames, whose TPR ceiling rises to what the frames can see.
#include <catch2/catch.hpp>

#include <fstream>
#include <regex>

#include <nlohmann/json.hpp>

#include "occsweep/eval/dataset.hpp"
#include "test_helpers.hpp"

using namespace occsweep;
namespace fs = std::filesystem;

namespace {

const fs::path kJoinMap = occsweep::test::sourceTree() / "tests" / "data" / "real" / "slambook_joinMap";

std::string q(const fs::path& p) { return test::shellQuoted(p); }

std::string ran(const std::string& args) {
  const auto r = test::runCli(args);
  INFO(args << "\n" << r.output);
  REQUIRE(r.exit_code == 0);
  return r.output;
}

// A 16-bit binary PGM of one depth everywhere (millimetres).
void writeFlatDepth(const fs::path& file, int width, int height, int millimetres) {
  std::ofstream out(file, std::ios::binary);
  out << "P5\n" << width << " " << height << "\n65535\n";
  for (int i = 0; i < width * height; ++i) out.put(char(millimetres >> 8)).put(char(millimetres & 255));
}

// World frame = the camera's at the origin (x right, y down, z forward). A wall 2 m ahead, wider and higher than
// the image; a box in the image; a box beside the camera, 75 degrees off its axis, 1 m away.
const char* const kWall = R"({"min": [-1.98, -1.48, 2.02], "max": [1.98, 1.48, 2.08]})";
const char* const kBoxInImage = R"({"min": [0.22, 0.12, 1.22], "max": [0.38, 0.28, 1.38]})";
const char* const kBoxBeside = R"({"min": [0.92, -0.08, 0.22], "max": [1.08, 0.08, 0.38]})";

// The data set `scans` with truth `boxes` (one region for all, so counts compare), in its own folder.
fs::path withTruth(const fs::path& scans, const std::string& name, const std::vector<const char*>& boxes) {
  const fs::path json = scans.parent_path() / (name + ".json"), out = scans.parent_path() / name;
  std::ofstream(json) << "[" << [&] {
    std::string s;
    for (const char* b : boxes) s += (s.empty() ? "" : ", ") + std::string(b);
    return s;
  }() << "]";
  ran("import truth " + q(json) + " --dataset " + q(scans) + " --out " + q(out) + " --region -2.5 -2 -0.5 2.5 2 2.5 --force");
  return out;
}

// TP + FN of `occsweep map` under `truth`: the truth voxels it counts.
std::uint64_t positives(const fs::path& dataset, const std::string& truth = "observable") {
  const std::string out = ran("map --dataset " + q(dataset) + " --method octomap --force --out " +
                              q(dataset.parent_path() / (dataset.filename().string() + ".ot")) + " --truth " + truth);
  std::smatch m;
  REQUIRE(std::regex_search(out, m, std::regex("TP (\\d+) FP \\d+ FN (\\d+)")));
  return std::stoull(m[1]) + std::stoull(m[2]);
}

nlohmann::json manifestOf(const fs::path& dataset) { return nlohmann::json::parse(test::bytesOf(dataset / "manifest.json")); }

// A folder holding the depth frame and its pose: the camera at the origin, unturned.
fs::path depthCameraFolder(const std::string& name) {
  const fs::path dir = test::scratch(name);
  writeFlatDepth(dir / "wall.pgm", 64, 48, 2000);
  std::ofstream(dir / "pose.txt") << "0 0 0 0 0 0 1\n";
  return dir;
}

}  // namespace

TEST_CASE("import depth records the camera: a box beside it, 75 degrees off its axis, is not observable") {
  const fs::path dir = depthCameraFolder("import-views-depth");
  ran("import depth " + q(dir / "wall.pgm") + " --poses " + q(dir / "pose.txt") +
      " --fx 50 --fy 50 --cx 31.5 --cy 23.5 --out " + q(dir / "camera"));
  const auto view = manifestOf(dir / "camera")["scans"][0]["view"];
  CHECK(view == nlohmann::json::parse(R"({"model": "pinhole", "fx": 50.0, "fy": 50.0, "cx": 31.5, "cy": 23.5,
      "width": 64, "height": 48, "rotation": [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]})"));
  const fs::path cam = dir / "camera";
  CHECK(positives(withTruth(cam, "beside", {kBoxBeside})) == 0);
  CHECK(positives(withTruth(cam, "beside", {kBoxBeside}), "full") > 0);
  CHECK(positives(withTruth(cam, "in-image", {kBoxInImage})) > 0);
  CHECK(positives(withTruth(cam, "all", {kWall, kBoxInImage, kBoxBeside})) ==
        positives(withTruth(cam, "wall-and-box", {kWall, kBoxInImage})));
  // The wall is seen where the image reaches it (2.56 x 1.92 m at 2 m of a 4 x 3 m wall), not beyond.
  const fs::path wall = withTruth(cam, "wall", {kWall});
  CHECK(positives(wall) > positives(wall, "full") / 3);
  CHECK(positives(wall) < positives(wall, "full") / 2);
  // A negative focal length mirrors the image: recorded as its mirror, the same pyramid, the same count.
  ran("import depth " + q(dir / "wall.pgm") + " --poses " + q(dir / "pose.txt") +
      " --fx 50 --fy -50 --cx 31.5 --cy 20.5 --out " + q(dir / "mirrored"));
  const auto mirrored = manifestOf(dir / "mirrored")["scans"][0]["view"];
  CHECK(mirrored["fy"] == 50.0);
  CHECK(mirrored["cy"] == 26.5);
}

TEST_CASE("import cloud --view-axis --view-half-angle: a box outside the cone is not observable, one inside is") {
  const fs::path dir = test::scratch("import-views-cone");
  std::ofstream(dir / "scan.xyz") << "0 0 2\n0.1 0 2\n0 0.1 2\n";
  ran("import cloud " + q(dir / "scan.xyz") + " --view-axis 0 0 1 --view-half-angle 30 --out " + q(dir / "cone"));
  CHECK(manifestOf(dir / "cone")["scans"][0]["view"] ==
        nlohmann::json::parse(R"({"model": "cone", "axis": [0.0, 0.0, 1.0], "half_angle_deg": 30.0})"));
  CHECK(positives(withTruth(dir / "cone", "in", {kBoxInImage})) > 0);
  CHECK(positives(withTruth(dir / "cone", "beside", {kBoxBeside})) == 0);
  // With a pose the axis is the sensor's: turned 90 degrees about y, +z becomes +x and the two boxes swap.
  std::ofstream(dir / "pose.txt") << "0 0 0 0 0.70710678 0 0.70710678\n";
  ran("import cloud " + q(dir / "scan.xyz") + " --poses " + q(dir / "pose.txt") +
      " --view-axis 0 0 1 --view-half-angle 30 --out " + q(dir / "turned"));
  CHECK(positives(withTruth(dir / "turned", "in", {kBoxInImage})) == 0);
  CHECK(positives(withTruth(dir / "turned", "beside", {kBoxBeside})) > 0);
  // 180 degrees is every direction, with no axis needed.
  ran("import cloud " + q(dir / "scan.xyz") + " --view-half-angle 180 --out " + q(dir / "sphere"));
  CHECK(manifestOf(dir / "sphere")["scans"][0]["view"] == nlohmann::json::parse(R"({"model": "sphere"})"));
  // Refused, exit 2, naming the flag, nothing written.
  for (const auto& [flags, says] : std::vector<std::pair<std::string, std::string>>{
           {"--view-axis 0 0 1 --view-half-angle 0", "--view-half-angle: must be in (0, 180] degrees"},
           {"--view-axis 0 0 1 --view-half-angle 181", "--view-half-angle: must be in (0, 180] degrees"},
           {"--view-axis 0 0 0 --view-half-angle 30", "--view-axis: must not be the zero vector"},
           // Old: accepted, and observable truth then held no voxel (the squared length underflowed or overflowed).
           {"--view-axis 1e-300 0 0 --view-half-angle 90", "--view-axis: must have a length from 1e-150 to 1e150"},
           {"--view-axis 1e155 0 0 --view-half-angle 90", "--view-axis: must have a length from 1e-150 to 1e150"},
           {"--view-axis 0 0 1", "--view-axis needs --view-half-angle"},
           {"--view-half-angle 60", "--view-half-angle 60 needs --view-axis X Y Z"}}) {
    const auto r = test::runCli("import cloud " + q(dir / "scan.xyz") + " " + flags + " --out " + q(dir / "bad"));
    INFO(flags << "\n" << r.output);
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.output, Catch::Contains(says));
    CHECK(!fs::exists(dir / "bad"));
  }
}

TEST_CASE("a data set without views reads as before and warns once, naming it, under observable truth") {
  const fs::path dir = test::scratch("import-views-none");
  std::ofstream(dir / "scan.xyz") << "0 0 2\n0.1 0 2\n0 0.1 2\n";
  ran("import cloud " + q(dir / "scan.xyz") + " --out " + q(dir / "plain"));
  CHECK(test::bytesOf(dir / "plain" / "manifest.json").find("\"view\"") == std::string::npos);
  const fs::path d = withTruth(dir / "plain", "beside", {kBoxBeside});
  const auto r = test::runCli("map --dataset " + q(d) + " --method octomap --out " + q(dir / "m.ot") + " --truth observable");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const std::string warning = "warning: " + d.string() + ": 1 of 1 scans record no sensor view";
  CHECK_THAT(r.output, Catch::Contains(warning));
  CHECK(r.output.find(warning) == r.output.rfind(warning));
  CHECK(positives(d) > 0);  // every direction, as before
  const auto full = test::runCli("map --dataset " + q(d) + " --method octomap --force --out " + q(dir / "m.ot"));
  CHECK(full.output.find("warning") == std::string::npos);  // full truth needs no view
}

TEST_CASE("the built-in scene records its camera with every scan and its observable truth stays 241 of 484") {
  const fs::path dir = test::scratch("import-views-scene");
  ran("scene --out " + q(dir / "scene"));
  const auto manifest = manifestOf(dir / "scene");
  REQUIRE(manifest.at("scans").size() == 24);
  for (const auto& scan : manifest.at("scans")) {
    REQUIRE(scan.contains("view"));
    CHECK(scan["view"]["model"] == "pinhole");
    CHECK(scan["view"]["width"] == 64);
    CHECK(scan["view"]["height"] == 48);
  }
  CHECK(positives(dir / "scene") == 241);
  CHECK(positives(dir / "scene", "full") == 484);
}

namespace {

// The highest TPR of any combination of an octomap-opt sweep under observable truth, and the truth voxels it counts.
std::pair<double, std::uint64_t> tprCeiling(const fs::path& dataset) {
  const fs::path out = dataset.parent_path() / (dataset.filename().string() + "-octomap-opt.json");
  ran("sweep --dataset " + q(dataset) + " --grid octomap-opt --truth observable --quiet --force --out " + q(out));
  const auto results = nlohmann::json::parse(test::bytesOf(out));
  double best = 0;
  for (const auto& m : results["maps"])
    for (const auto& t : m["thresholds"])
      if (t["tpr"].is_number()) best = std::max(best, t["tpr"].get<double>());
  const auto& first = results["maps"][0]["thresholds"][0];
  return {best, first["tp"].get<std::uint64_t>() + first["fn"].get<std::uint64_t>()};
}

// The frames' own points as an ascii PLY: truth of what the frames measured, near or far.
void writePointsPly(const Dataset& d, const fs::path& file) {
  std::ofstream out(file);
  out << "ply\nformat ascii 1.0\nelement vertex " << pointCount(d.scans)
      << "\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
  out.precision(9);
  for (const Scan& s : d.scans)
    for (const auto& p : s.points) out << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
}

}  // namespace

TEST_CASE("slambook joinMap frames: with the cameras' views the best TPR under observable truth reaches what they see") {
  // docs/import.md, "Sensor views": the 5 frames at stride 4 (as docs/import.md's table), truth = their own points
  // (8,391 voxels at 0.1 m). Without views, an origin "saw" every unoccluded truth voxel within s_c = 4 m in any
  // direction: voxels that only a frame farther than 4 m measured counted, and no map can reach them.
  const fs::path dir = test::scratch("import-views-joinmap");
  std::string images;
  for (int i = 1; i <= 5; ++i) images += q(kJoinMap / "depth" / (std::to_string(i) + ".pgm")) + " ";
  ran("import depth " + images + "--poses " + q(kJoinMap / "pose.txt") + " --fx 518 --fy 519 --cx 325.5 --cy 253.5 "
      "--max-depth 7 --stride 4 --out " + q(dir / "frames"));
  writePointsPly(readDataset(dir / "frames"), dir / "points.ply");
  ran("import truth " + q(dir / "points.ply") + " --dataset " + q(dir / "frames") + " --out " + q(dir / "cameras"));
  // The same data set with its views taken out: the rule before views.
  fs::copy(dir / "cameras", dir / "origins", fs::copy_options::recursive);
  auto m = manifestOf(dir / "cameras");
  for (auto& scan : m["scans"]) scan.erase("view");
  std::ofstream(dir / "origins" / "manifest.json") << m.dump(1) << '\n';

  const auto [with_views, seen_by_cameras] = tprCeiling(dir / "cameras");
  const auto [without_views, seen_from_origins] = tprCeiling(dir / "origins");
  CHECK(seen_from_origins == 1760);
  CHECK(seen_by_cameras == 1213);
  CHECK(without_views < 0.83);
  CHECK(with_views > 0.99);
}
