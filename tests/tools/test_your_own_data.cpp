// docs/your-own-data.md, run as it stands: small synthetic recordings in the TUM RGB-D, 3DMatch and Replica
// (NICE-SLAM / nvblox) layouts, rendered at each data set's image size and intrinsics with its depth units and pose
// files, then the page's command blocks (its own layout's import, then the common steps) run by the shell in a
// folder where `rec/` is the recording. OCCSWEEP_TEST_CLI=/path/to/old/occsweep runs them against another build.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <optional>
#include <sstream>

#include <nlohmann/json.hpp>

#include "depth_png.hpp"
#include "occsweep/eval/dataset.hpp"
#include "test_helpers.hpp"

namespace fs = std::filesystem;
using Catch::Matchers::Contains;
using namespace occsweep;

namespace {

struct Box {
  std::array<double, 3> min, max;
};
// The scene: a 0.8 m box standing on a 6 m floor slab.
const std::vector<Box> kScene = {{{-0.4, -0.4, 0.0}, {0.4, 0.4, 0.8}}, {{-3, -3, -0.1}, {3, 3, 0.0}}};

struct Camera {
  int width, height;
  double fx, fy, cx, cy, depth_scale;
  double invalid = 0;  // the raw value of a pixel without depth: 0, or 65535 in 7-Scenes and 3DMatch
};

// Camera-to-world rotation (columns: image right, image down, viewing direction) and position.
struct Pose {
  std::array<double, 9> r;  // row-major
  std::array<double, 3> t;
};

// At frame time f (0 to 3) on a circle of 2.5 m around the box, 1.2 m up, looking at the box's centre.
Pose orbitPose(double f) {
  const double a = 0.5 * f;
  const std::array<double, 3> eye{2.5 * std::cos(a), 2.5 * std::sin(a), 1.2}, target{0, 0, 0.4};
  std::array<double, 3> z{target[0] - eye[0], target[1] - eye[1], target[2] - eye[2]};
  const double zn = std::sqrt(z[0] * z[0] + z[1] * z[1] + z[2] * z[2]);
  for (double& c : z) c /= zn;
  std::array<double, 3> x{z[1], -z[0], 0.0};  // z x up, up = +z: right in the image
  const double xn = std::hypot(x[0], x[1]);
  x = {x[0] / xn, x[1] / xn, 0};
  const std::array<double, 3> y{z[1] * x[2] - z[2] * x[1], z[2] * x[0] - z[0] * x[2], z[0] * x[1] - z[1] * x[0]};
  return {{x[0], y[0], z[0], x[1], y[1], z[1], x[2], y[2], z[2]}, eye};
}

// The same pose world to camera: what a pose file in the other convention holds ([R^T | -R^T t]).
Pose inverted(const Pose& p) {
  Pose q{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) q.r[i * 3 + j] = p.r[j * 3 + i];
  for (int i = 0; i < 3; ++i) q.t[i] = -(q.r[i * 3] * p.t[0] + q.r[i * 3 + 1] * p.t[1] + q.r[i * 3 + 2] * p.t[2]);
  return q;
}

// Depth along the optical axis to the nearest box, by the slab method; none when the ray misses.
std::optional<double> depthAt(const Pose& p, const Camera& c, int u, int v) {
  const std::array<double, 3> d_cam{(u - c.cx) / c.fx, (v - c.cy) / c.fy, 1.0};
  std::array<double, 3> d{};
  for (int i = 0; i < 3; ++i) d[i] = p.r[i * 3] * d_cam[0] + p.r[i * 3 + 1] * d_cam[1] + p.r[i * 3 + 2] * d_cam[2];
  std::optional<double> best;
  for (const Box& b : kScene) {
    double near = 0, far = 1e9;
    for (int i = 0; i < 3; ++i) {
      if (std::abs(d[i]) < 1e-12) {
        if (p.t[i] < b.min[i] || p.t[i] > b.max[i]) near = far + 1;
        continue;
      }
      double t0 = (b.min[i] - p.t[i]) / d[i], t1 = (b.max[i] - p.t[i]) / d[i];
      if (t0 > t1) std::swap(t0, t1);
      near = std::max(near, t0), far = std::min(far, t1);
    }
    if (near <= far && near > 0 && (!best || near < *best)) best = near;  // d_cam.z = 1: t is the depth
  }
  return best;
}

void writeDepthPng(const fs::path& file, const Pose& p, const Camera& c) {
  test::writeDepthPng(file, c.width, c.height, [&](int u, int v) {
    const auto z = depthAt(p, c, u, v);
    return std::uint16_t(z ? std::min(65535.0, std::round(*z * c.depth_scale)) : c.invalid);
  });
}

std::string matrixRows(const Pose& p, const char* row_end) {
  std::ostringstream s;
  s << std::setprecision(17);
  for (int i = 0; i < 3; ++i) s << p.r[i * 3] << ' ' << p.r[i * 3 + 1] << ' ' << p.r[i * 3 + 2] << ' ' << p.t[i] << row_end;
  s << "0 0 0 1\n";
  return s.str();
}

// TUM's qx qy qz qw of a rotation matrix (Shepperd's method, the largest diagonal first).
std::array<double, 4> quaternion(const std::array<double, 9>& r) {
  const double tr = r[0] + r[4] + r[8];
  std::array<double, 4> q{};  // x y z w
  if (tr > 0) {
    const double s = 2 * std::sqrt(1 + tr);
    q = {(r[7] - r[5]) / s, (r[2] - r[6]) / s, (r[3] - r[1]) / s, s / 4};
  } else if (r[0] > r[4] && r[0] > r[8]) {
    const double s = 2 * std::sqrt(1 + r[0] - r[4] - r[8]);
    q = {s / 4, (r[1] + r[3]) / s, (r[2] + r[6]) / s, (r[7] - r[5]) / s};
  } else if (r[4] > r[8]) {
    const double s = 2 * std::sqrt(1 + r[4] - r[0] - r[8]);
    q = {(r[1] + r[3]) / s, s / 4, (r[5] + r[7]) / s, (r[2] - r[6]) / s};
  } else {
    const double s = 2 * std::sqrt(1 + r[8] - r[0] - r[4]);
    q = {(r[2] + r[6]) / s, (r[5] + r[7]) / s, s / 4, (r[3] - r[1]) / s};
  }
  return q;
}

// The box (12 triangles) and the floor under it (2 triangles) as an ASCII PLY mesh.
void writeMesh(const fs::path& file) {
  std::vector<std::array<double, 3>> v;
  for (int i = 0; i < 8; ++i) v.push_back({i & 1 ? 0.4 : -0.4, i & 2 ? 0.4 : -0.4, i & 4 ? 0.8 : 0.0});
  for (const auto& corner : {std::array<double, 3>{-1.5, -1.5, 0}, {1.5, -1.5, 0}, {1.5, 1.5, 0}, {-1.5, 1.5, 0}})
    v.push_back(corner);
  const std::vector<std::array<int, 3>> faces = {{0, 1, 3}, {0, 3, 2}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                                                 {2, 3, 7}, {2, 7, 6}, {0, 2, 6}, {0, 6, 4}, {1, 3, 7}, {1, 7, 5},
                                                 {8, 9, 10}, {8, 10, 11}};
  std::ofstream out(file);
  out << "ply\nformat ascii 1.0\nelement vertex " << v.size() << "\nproperty float x\nproperty float y\n"
      << "property float z\nelement face " << faces.size() << "\nproperty list uchar int vertex_indices\nend_header\n";
  for (const auto& p : v) out << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
  for (const auto& f : faces) out << "3 " << f[0] << ' ' << f[1] << ' ' << f[2] << '\n';
}

// The walls of a 9.9 m square room around the scene, 3 m high: truth that no frame sees (beyond s_c = 4 m, or
// outside the images). They stand on voxel centres, not on the faces between voxels.
void writeRoomWalls(const fs::path& file) {
  std::ofstream out(file);
  out << "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\nproperty float z\n"
      << "element face 8\nproperty list uchar int vertex_indices\nend_header\n";
  const std::array<std::array<double, 2>, 4> corners{{{-4.95, -4.95}, {4.95, -4.95}, {4.95, 4.95}, {-4.95, 4.95}}};
  for (const double z : {0, 3})
    for (const auto& c : corners) out << c[0] << ' ' << c[1] << ' ' << z << '\n';
  for (int w = 0; w < 4; ++w)
    out << "3 " << w << ' ' << (w + 1) % 4 << ' ' << 4 + (w + 1) % 4 << "\n3 " << w << ' ' << 4 + (w + 1) % 4 << ' '
        << 4 + w << '\n';
}

// A recording in `layout` under `rec`, four frames, with the camera its intrinsics (the page's flags or the layout's
// intrinsics file) give; 3DMatch's pose files hold world-to-camera poses when `world_to_camera` (the other
// convention); the 3DMatch pose files' positions are moved by `shift` (a pose error; the images stay).
void writeRecording(const std::string& layout, const fs::path& rec, bool world_to_camera = false,
                    const std::array<double, 3>& shift = {}) {
  fs::create_directories(rec);
  writeMesh(rec / "mesh.ply");
  if (layout == "tum") {
    const Camera c{640, 480, 525, 525, 319.5, 239.5, 5000};
    fs::create_directories(rec / "depth");
    std::ofstream gt(rec / "groundtruth.txt");
    gt << "# ground truth trajectory\n# timestamp tx ty tz qx qy qz qw\n" << std::setprecision(17);
    // Ground truth at 100 Hz over the four frames' span; depth images at about 30 Hz, named by their timestamps.
    for (int i = 0; i <= 100; ++i) {
      const Pose at = orbitPose(i / 33.0);  // frame f at i = 33 f
      const auto q = quaternion(at.r);
      gt << 1305031102.0 + 0.01 * i << ' ' << at.t[0] << ' ' << at.t[1] << ' ' << at.t[2] << ' ' << q[0] << ' '
         << q[1] << ' ' << q[2] << ' ' << q[3] << '\n';
    }
    for (int f = 0; f < 4; ++f) {
      std::ostringstream name;
      name << std::fixed << std::setprecision(6) << 1305031102.0 + 0.33 * f + 0.003 << ".png";
      writeDepthPng(rec / "depth" / name.str(), orbitPose(f), c);
    }
  } else if (layout == "3dmatch") {
    const Camera c{640, 480, 570.3422241210938, 570.3422241210938, 320, 240, 1000, 65535};
    std::ofstream k(rec / "camera-intrinsics.txt");  // as numpy.savetxt writes it, tab-separated
    const std::array<double, 9> matrix{c.fx, 0, c.cx, 0, c.fy, c.cy, 0, 0, 1};
    k << std::scientific << std::setprecision(18);
    for (std::size_t i = 0; i < 9; ++i) k << matrix[i] << (i % 3 == 2 ? '\n' : '\t');
    fs::create_directories(rec / "seq-01");
    for (int f = 0; f < 4; ++f) {
      const std::string frame = "frame-00000" + std::to_string(f);
      writeDepthPng(rec / "seq-01" / (frame + ".depth.png"), orbitPose(f), c);
      Pose pose = world_to_camera ? inverted(orbitPose(f)) : orbitPose(f);
      for (std::size_t a = 0; a < 3; ++a) pose.t[a] += shift[a];
      std::ofstream(rec / "seq-01" / (frame + ".pose.txt")) << matrixRows(pose, "\n");
    }
  } else {  // replica: NICE-SLAM's Replica/room0/ with Replica/cam_params.json beside it
    const Camera c{1200, 680, 600, 600, 599.5, 339.5, 6553.5};
    std::ofstream(rec.parent_path() / "cam_params.json")
        << R"({"camera": {"w": 1200, "h": 680, "fx": 600.0, "fy": 600.0, "cx": 599.5, "cy": 339.5, "scale": 6553.5}})";
    fs::create_directories(rec / "results");
    std::ofstream traj(rec / "traj.txt");
    for (int i = 0; i < 2000; ++i) {  // the whole trajectory, 16 numbers a line; frame i at time i / 100
      std::string rows = matrixRows(orbitPose(i / 100.0), " ");
      std::replace(rows.begin(), rows.end(), '\n', ' ');
      traj << rows << '\n';
    }
    for (int f = 0; f < 4; ++f) {  // depth000000.png, depth000100.png, ...: the frames the page's block takes
      std::ostringstream name;
      name << "depth" << std::setw(6) << std::setfill('0') << 100 * f << ".png";
      writeDepthPng(rec / "results" / name.str(), orbitPose(f), c);
    }
  }
}

// The page with its line breaks as spaces: a line the page wraps reads as the program prints it.
std::string pageText() {
  std::string text = test::bytesOf(occsweep::test::sourceTree() / "docs" / "your-own-data.md");
  std::replace(text.begin(), text.end(), '\n', ' ');
  return text;
}

// The line of `output` that starts with `start` ("" when none).
std::string lineStarting(const std::string& output, const std::string& start) {
  std::istringstream lines(output);
  for (std::string line; std::getline(lines, line);)
    if (line.rfind(start, 0) == 0) return line;
  return "";
}

// The shell commands of the page's block `name` (between `<!-- walkthrough: NAME -->` and the next end marker),
// continuation lines joined.
std::vector<std::string> walkthroughCommands(const std::string& name) {
  std::ifstream in(occsweep::test::sourceTree() / "docs" / "your-own-data.md");
  std::vector<std::string> commands;
  bool inside = false;
  std::string pending;
  for (std::string line; std::getline(in, line);) {
    if (line == "<!-- walkthrough: " + name + " -->") inside = true;
    else if (line == "<!-- end walkthrough -->") inside = false;
    else if (inside && (line.rfind("occsweep ", 0) == 0 || !pending.empty())) {
      const bool more = !line.empty() && line.back() == '\\';
      pending += more ? line.substr(0, line.size() - 1) : line;
      if (!more) commands.push_back(pending), pending.clear();
    }
  }
  return commands;
}

}  // namespace

TEST_CASE("docs/your-own-data.md runs as written on a TUM, a 3DMatch and a Replica recording") {
  const std::vector<std::string> common = walkthroughCommands("common");
  REQUIRE(common.size() == 5);
  for (const std::string layout : {"tum", "3dmatch", "replica"}) {
    INFO("layout " << layout);
    const fs::path dir = test::scratch("your-own-data-" + layout);
    writeRecording(layout, dir / "rec");
    std::vector<std::string> commands = walkthroughCommands(layout);
    REQUIRE(commands.size() == 1);
    commands.insert(commands.end(), common.begin(), common.end());
    for (const std::string& command : commands) {
      const std::string line = "cd " + test::shellQuoted(dir) + " && " + test::shellQuoted(test::cliUnderTest()) +
                               command.substr(std::string("occsweep").size()) + " 2>&1";
      const auto r = test::runShell(line);
      INFO(command << "\n" << r.output);
      REQUIRE(r.exit_code == 0);
      CHECK_THAT(r.output, !Contains("warning: a median depth"));  // the layout's depth scale is the right one
      CHECK_THAT(r.output, !Contains(": warning: "));  // nor a coverage or alignment warning: the frames see the box
      if (layout == "3dmatch" && command.find("import truth") != std::string::npos)
        CHECK_THAT(pageText(), Contains(lineStarting(r.output, "truth coverage")));  // the page shows it as it is
    }
    CHECK(test::bytesOf(dir / "curves.pdf").rfind("%PDF-", 0) == 0);
    CHECK(test::bytesOf(dir / "budget.pdf").rfind("%PDF-", 0) == 0);
    CHECK_THAT(test::bytesOf(dir / "table.tex"), Contains("\\begin{tabular}"));
    // The recording sees the box: the k-NN maps find truth voxels (an import off by a scale or a pose convention
    // would put every point outside the region and score no true positive).
    const auto check = test::runShell(test::shellQuoted(test::cliUnderTest()) + " results check " +
                                      test::shellQuoted(dir / "knn.json") + " --dataset " +
                                      test::shellQuoted(dir / "ds-truth") + " 2>&1");
    INFO(check.output);
    CHECK(check.exit_code == 0);
    const auto results = nlohmann::json::parse(std::ifstream(dir / "knn.json"));
    std::uint64_t best_tp = 0;
    for (const auto& m : results.at("maps"))
      for (const auto& t : m.at("thresholds")) best_tp = std::max<std::uint64_t>(best_tp, t.at("tp").get<std::uint64_t>());
    CHECK(best_tp > 20);
  }
}

namespace {

// The 3DMatch recording imported as the page's block does (its frames' pose files in whichever convention), with
// `flags` more.
fs::path importedRecording(const std::string& name, bool world_to_camera, const std::array<double, 3>& shift = {},
                           const std::string& flags = "") {
  const fs::path dir = test::scratch(name);
  writeRecording("3dmatch", dir / "rec", world_to_camera, shift);
  const auto r = test::runIn(dir, "import depth rec/seq-01/frame-*.depth.png --poses rec/seq-01/frame-*.pose.txt "
                                  "--pose-format matrix --depth-scale 1000 --max-depth 10 --fx 585 --fy 585 --cx 320 "
                                  "--cy 240 --stride 8 --out ds" + flags);
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  return dir;
}

// What an alignment warning names as its causes (docs/import.md, "Truth coverage and alignment"): a shift first, as
// likely as the other convention, whose fix is a flag.
const std::string kCauses = "likely causes: the truth or the poses shifted (a pose error, or the truth in another "
                            "frame), poses written world to camera (import with --pose-convention world-to-camera)";

// TP + FN of every threshold of a results file: the truth voxels it counts.
std::uint64_t countedTruth(const fs::path& results) {
  const auto t = nlohmann::json::parse(std::ifstream(results)).at("maps").at(0).at("thresholds").at(0);
  return t.at("tp").get<std::uint64_t>() + t.at("fn").get<std::uint64_t>();
}

// The notes of `compare RESULTS` (its --json rows'), which it also prints under the table.
std::string compareNotes(const fs::path& dir, const std::string& results) {
  const auto compare = test::runIn(dir, "compare " + results + " --json compare.json --force");
  INFO(compare.output);
  REQUIRE(compare.exit_code == 0);
  return nlohmann::json::parse(std::ifstream(dir / "compare.json")).at("rows").at(0).at("notes").dump();
}

}  // namespace

TEST_CASE("import truth, sweep and compare warn when the frames see a small part of the truth, naming --truth "
          "observable") {
  const fs::path dir = importedRecording("coverage-partial", false);
  writeRoomWalls(dir / "rec" / "room.ply");
  SECTION("the box and its floor, which the frames see: coverage printed, no warning") {
    const auto truth = test::runIn(dir, "import truth rec/mesh.ply --dataset ds --out ds-box");
    INFO(truth.output);
    REQUIRE(truth.exit_code == 0);
    CHECK_THAT(truth.output, Contains("truth coverage at 0.1 m, s_c 4 m: "));
    CHECK_THAT(truth.output, !Contains("warning"));
    for (const std::string mode : {"full", "observable"}) {
      const auto sweep = test::runIn(dir, "sweep --dataset ds-box --grid octomap-opt --truth " + mode + " --out " +
                                              mode + ".json");
      INFO(sweep.output);
      REQUIRE(sweep.exit_code == 0);
      CHECK_THAT(sweep.output, Contains("truth coverage at 0.1 m") && !Contains("warning"));
    }
    // Fewer truth voxels than the sample: every one tested, so the counts are observable truth's own.
    const auto coverage = nlohmann::json::parse(std::ifstream(dir / "full.json")).at("dataset").at("coverage");
    CHECK(coverage.at("truth_voxels") == countedTruth(dir / "full.json"));
    CHECK(coverage.at("sampled_truth_voxels") == coverage.at("truth_voxels"));
    CHECK(coverage.at("observable_sampled") == countedTruth(dir / "observable.json"));
    CHECK(coverage.at("median_point_distance").get<double>() <= 0.2);
  }
  SECTION("the room's walls too, which no frame sees: a warning naming --truth observable, in import, sweep and "
          "compare; the page's sweep under observable truth") {
    const auto truth = test::runIn(dir, "import truth rec/mesh.ply rec/room.ply --dataset ds --out ds-truth");
    INFO(truth.output);
    REQUIRE(truth.exit_code == 0);
    const std::string warning = lineStarting(truth.output, "occsweep import: warning: ds-truth: only ");
    CHECK_THAT(warning, Contains("of the truth voxels are observable") && Contains("--truth observable") &&
                            Contains("--region"));
    CHECK_THAT(pageText(), Contains(warning));  // docs/your-own-data.md shows this recording's warning as it is
    const auto sweep = test::runIn(dir, "sweep --dataset ds-truth --grid octomap-opt --out room.json");
    INFO(sweep.output);
    REQUIRE(sweep.exit_code == 0);
    CHECK_THAT(sweep.output, Contains("occsweep sweep: warning: ds-truth: only ") && Contains("--truth observable"));
    CHECK_THAT(sweep.output, !Contains("not aligned"));  // the points lie on the truth: only the share is low
    CHECK_THAT(compareNotes(dir, "room.json"), Contains("of the truth voxels are observable from the scans") &&
                                                  Contains("--truth observable"));
    // A results store records it alike; counts that cannot hold are refused as a hand edit, naming the field.
    REQUIRE(test::runIn(dir, "sweep --dataset ds-truth --grid octomap-opt --out room.db").exit_code == 0);
    CHECK_THAT(compareNotes(dir, "room.db"), Contains("--truth observable"));
    auto edited = nlohmann::json::parse(std::ifstream(dir / "room.json"));
    auto& coverage = edited["dataset"]["coverage"];
    coverage["observable_sampled"] = coverage["sampled_truth_voxels"].get<int>() + 1;  // more seen than tested
    std::ofstream(dir / "edited.json") << edited.dump();
    const auto check = test::runIn(dir, "results check edited.json");
    CHECK(check.exit_code == 2);
    CHECK_THAT(check.output, Contains("edited.json: dataset.coverage: counts that cannot hold (edited by hand?)"));
    // The page's sweep for such a recording: under observable truth the share is what it measures, no warning.
    const std::vector<std::string> partial = walkthroughCommands("partial");
    REQUIRE(partial.size() == 1);
    const auto observable = test::runIn(dir, partial.front().substr(std::string("occsweep ").size()));
    INFO(observable.output);
    REQUIRE(observable.exit_code == 0);
    CHECK_THAT(observable.output, Contains("truth coverage") && !Contains("warning"));
    const auto compare = test::runIn(dir, "compare octomap.json knn.json");
    INFO(compare.output);
    CHECK_THAT(compare.output, Contains("truth: observable") && !Contains("note: ds: only"));
  }
}

TEST_CASE("a truth of the scan's own points, hidden behind one another at the voxel size, is not called a small part "
          "observable") {
  // As Middlebury's Aloe truth at 0.1 m: a block of points 1 m deep seen from one side; truth = the same points. A
  // ray at voxel resolution reaches the front voxels only, but every truth voxel holds a point, which the maps mark
  // occupied. The old binary: "only 10 % of the truth voxels are observable ...: under full truth every map misses
  // the rest".
  const fs::path dir = test::scratch("coverage-own-points");
  std::ofstream cloud(dir / "block.xyz"), ply(dir / "block.ply");
  const int side = 25;  // points 0.04 m apart in a 1 m cube, 2 to 6 m from the sensor
  ply << "ply\nformat ascii 1.0\nelement vertex " << side * side * side
      << "\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
  for (int i = 0; i < side; ++i)
    for (int j = 0; j < side; ++j)
      for (int k = 0; k < side; ++k) {
        const std::string p = std::to_string(2.02 + 0.04 * i) + " " + std::to_string(-0.48 + 0.04 * j) + " " +
                              std::to_string(0.02 + 0.04 * k) + "\n";
        cloud << p, ply << p;
      }
  cloud.close(), ply.close();
  REQUIRE(test::runIn(dir, "import cloud block.xyz --origin 0 0 0.5 --out scans").exit_code == 0);
  const auto truth = test::runIn(dir, "import truth block.ply --dataset scans --out ds");
  INFO(truth.output);
  REQUIRE(truth.exit_code == 0);
  CHECK_THAT(truth.output, Contains("truth coverage at 0.1 m") && Contains(", 100 % holding a point"));
  CHECK_THAT(truth.output, !Contains("warning"));
  const auto sweep = test::runIn(dir, "sweep --dataset ds --grid octomap-opt --out full.json");
  INFO(sweep.output);
  REQUIRE(sweep.exit_code == 0);
  CHECK_THAT(sweep.output, !Contains("warning"));
}

TEST_CASE("import truth and sweep warn when the poses were written world to camera, naming the convention and the "
          "flag that reads it") {
  const fs::path dir = importedRecording("coverage-inverted", true);
  const auto truth = test::runIn(dir, "import truth rec/mesh.ply --dataset ds --out ds-truth");
  INFO(truth.output);
  REQUIRE(truth.exit_code == 0);
  const std::string fix = "scans and truth are not aligned; " + kCauses;
  CHECK_THAT(truth.output, Contains("occsweep import: warning: ds-truth: ") && Contains(fix));
  const auto sweep = test::runIn(dir, "sweep --dataset ds-truth --grid octomap-opt --out full.json");
  INFO(sweep.output);
  REQUIRE(sweep.exit_code == 0);
  CHECK_THAT(sweep.output, Contains("occsweep sweep: warning: ds-truth: ") && Contains(fix));
  // Misaligned, observable truth is not the fix: only the poses' warning is given.
  CHECK_THAT(truth.output + sweep.output, !Contains("--truth observable"));
  CHECK_THAT(compareNotes(dir, "full.json"), Contains("the points lie a median") && Contains(fix));
}

TEST_CASE("import truth, sweep and compare warn when the poses are shifted by 0.5 to 1.5 m, naming the offset that "
          "fits and the fix") {
  // Most points stay on the floor slab, so their median distance to the truth stays within 2 voxels; moved back by
  // the shift, the box's points fit too (docs/import.md, "Truth coverage and alignment").
  const std::vector<std::array<double, 3>> shifts{{1.5, 0, 0}, {0, 1.5, 0}, {0.5, 0, 0}, {0, -0.5, 0}, {-1, 1, 0}};
  for (std::size_t i = 0; i < shifts.size(); ++i) {
    const auto& shift = shifts[i];
    INFO("poses shifted by " << shift[0] << ", " << shift[1] << ", " << shift[2] << " m");
    const fs::path dir = importedRecording("coverage-shift-" + std::to_string(i), false, shift);
    const auto truth = test::runIn(dir, "import truth rec/mesh.ply --dataset ds --out ds-truth");
    INFO(truth.output);
    REQUIRE(truth.exit_code == 0);
    const std::string warning = lineStarting(truth.output, "occsweep import: warning: ds-truth: ");
    CHECK_THAT(warning, Contains("one translation fits them clearly better than none: ") &&
                            Contains("scans and truth are not aligned; " + kCauses));
    // The offset named undoes the shift, within a voxel on each axis.
    const std::size_t at = warning.find("moved by the best offset (");
    REQUIRE(at != std::string::npos);
    std::istringstream offset(warning.substr(at + 26));
    std::array<double, 3> found{};
    char comma = 0;
    offset >> found[0] >> comma >> found[1] >> comma >> found[2];
    for (std::size_t a = 0; a < 3; ++a) CHECK(found[a] == Approx(-shift[a]).margin(0.11));
    if (i > 0) continue;  // sweep and compare once: the results record the offset, compare warns from them
    const auto sweep = test::runIn(dir, "sweep --dataset ds-truth --grid octomap-opt --out full.json");
    INFO(sweep.output);
    REQUIRE(sweep.exit_code == 0);
    CHECK_THAT(sweep.output, Contains("occsweep sweep: warning: ds-truth: ") &&
                                 Contains("one translation fits them clearly better"));
    CHECK_THAT(compareNotes(dir, "full.json"), Contains("one translation fits them clearly better"));
  }
}

TEST_CASE("import depth --pose-convention world-to-camera reads world-to-camera pose files as the camera-to-world "
          "ones, aligned with the truth") {
  const fs::path right = importedRecording("convention-camera-to-world", false);
  const fs::path read = importedRecording("convention-world-to-camera", true, {},
                                          " --pose-convention world-to-camera");
  const Dataset a = readDataset(right / "ds"), b = readDataset(read / "ds");
  REQUIRE(a.scans.size() == b.scans.size());
  for (std::size_t s = 0; s < a.scans.size(); ++s) {
    INFO("scan " << s);
    CHECK((a.scans[s].origin - b.scans[s].origin).norm() <= 1e-5);
    REQUIRE(a.scans[s].points.size() == b.scans[s].points.size());
    for (std::size_t i = 0; i < a.scans[s].points.size(); ++i)
      CHECK((a.scans[s].points[i] - b.scans[s].points[i]).norm() <= 1e-5);
  }
  CHECK(a.source.at("pose_convention") == "camera-to-world");  // the data set says how its poses were read
  CHECK(b.source.at("pose_convention") == "world-to-camera");
  const auto truth = test::runIn(read, "import truth rec/mesh.ply --dataset ds --out ds-truth");
  INFO(truth.output);
  REQUIRE(truth.exit_code == 0);
  CHECK_THAT(truth.output, Contains("truth coverage at 0.1 m") && !Contains("warning"));
}

TEST_CASE("a shift past the offset search (3 m, the search reaches 2 m) still warns, naming the distance and both "
          "causes") {
  const fs::path dir = importedRecording("coverage-shift-far", false, {3, 0, 0});
  const auto truth = test::runIn(dir, "import truth rec/mesh.ply --dataset ds --out ds-truth");
  INFO(truth.output);
  REQUIRE(truth.exit_code == 0);
  const std::string warning = lineStarting(truth.output, "occsweep import: warning: ds-truth: ");
  CHECK_THAT(warning, Contains("the points lie a median ") && Contains(" m (") &&
                          Contains("scans and truth are not aligned; " + kCauses));
}
