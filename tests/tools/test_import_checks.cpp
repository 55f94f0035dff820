// The usual mistakes of importing one's own recording (docs/import.md, "Poses", "Intrinsics files" and "Depth
// scale"), through the command: a pose file in another format's shape, poses one file per frame (3DMatch), a TUM
// trajectory of more poses than images, a whole trajectory read by frame number (Replica), the layouts' intrinsics
// files, and a wrong --depth-scale. OCCSWEEP_TEST_CLI=/path/to/old/occsweep runs them against another build.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <regex>
#include <sstream>
#include <tuple>
#include <utility>
#include <vector>

#include "depth_png.hpp"
#include "occsweep/eval/dataset.hpp"
#include "test_helpers.hpp"

using namespace occsweep;
namespace fs = std::filesystem;
using Catch::Matchers::Contains;

namespace {

constexpr int kWidth = 4, kHeight = 3;
const std::string kCamera = " --fx 2 --fy 2 --cx 1.5 --cy 1";

// A 16-bit binary PGM of `raw` at every pixel but one, which holds raw + 1 + frame (so that frames differ).
void writeDepth(const fs::path& file, std::uint16_t raw, int frame) {
  std::string body;
  for (int i = 0; i < kWidth * kHeight; ++i) {
    const auto v = std::uint16_t(i == 5 ? raw + 1 + frame : raw);
    body += char(v >> 8), body += char(v & 0xff);  // big-endian
  }
  std::ofstream(file, std::ios::binary) << "P5\n" << kWidth << ' ' << kHeight << "\n65535\n" << body;
}

// A camera-to-world pose with identity rotation at (x, y, z), as a 4x4 matrix.
std::string matrixPose(double x, double y, double z) {
  std::ostringstream s;
  s << "1 0 0 " << x << "\n0 1 0 " << y << "\n0 0 1 " << z << "\n0 0 0 1\n";
  return s.str();
}

test::CommandResult importDepth(const std::string& images, const std::string& poses, const std::string& more,
                                const fs::path& out) {
  return test::runCli("import depth " + images + " --poses " + poses + kCamera + more + " --out " + out.string());
}

// An 8x6 16-bit PNG as RGB-D recordings store depth: raw values 1500 + 10 u + 7 v + 100 frame, one pixel unmeasured.
fs::path writeFramePng(const fs::path& file, int frame) {
  test::writeDepthPng(file, 8, 6, [frame](int u, int v) {
    return std::uint16_t(u == 2 && v == 3 ? 0 : 1500 + 10 * u + 7 * v + 100 * frame);
  });
  return file;
}

test::CommandResult importWith(const std::string& frames_and_poses, const std::string& flags, const fs::path& out) {
  return test::runCli("import depth " + frames_and_poses + " " + flags + " --out " + out.string());
}

// Each `import depth ARGS` refused: exit 2, its message, nothing written at `out`.
void requireRefused(const std::vector<std::pair<std::string, std::string>>& args_and_messages, const fs::path& out) {
  for (const auto& [args, message] : args_and_messages) {
    const auto r = importWith(args, "", out);
    INFO(args << ": " << r.output);
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.output, Contains(message));
    CHECK_FALSE(fs::exists(out));
  }
}

// Two data sets hold the same scans: points and origins, within `metres` (0: equal).
void requireSameScans(const fs::path& a, const fs::path& b, double metres = 0) {
  const Dataset x = readDataset(a), y = readDataset(b);
  REQUIRE(x.scans.size() == y.scans.size());
  for (std::size_t s = 0; s < x.scans.size(); ++s) {
    INFO("scan " << s);
    CHECK((x.scans[s].origin - y.scans[s].origin).norm() <= metres);
    REQUIRE(x.scans[s].points.size() == y.scans[s].points.size());
    for (std::size_t i = 0; i < x.scans[s].points.size(); ++i)
      CHECK((x.scans[s].points[i] - y.scans[s].points[i]).norm() <= metres);
  }
}

// A camera-to-world pose: the rotation of the unit quaternion (x, y, z, w) and the translation t.
struct QuaternionPose {
  std::array<double, 4> q;
  std::array<double, 3> t;
};

std::array<double, 9> rotationOf(const std::array<double, 4>& q) {
  const auto [x, y, z, w] = q;
  return {1 - 2 * (y * y + z * z), 2 * (x * y - z * w),     2 * (x * z + y * w),
          2 * (x * y + z * w),     1 - 2 * (x * x + z * z), 2 * (y * z - x * w),
          2 * (x * z - y * w),     2 * (y * z + x * w),     1 - 2 * (x * x + y * y)};
}

// The same transform world to camera: the conjugate rotation and -R^T t.
QuaternionPose worldToCamera(const QuaternionPose& p) {
  const std::array<double, 9> r = rotationOf(p.q);
  QuaternionPose inverse{{-p.q[0], -p.q[1], -p.q[2], p.q[3]}, {}};
  for (std::size_t i = 0; i < 3; ++i) inverse.t[i] = -(r[i] * p.t[0] + r[3 + i] * p.t[1] + r[6 + i] * p.t[2]);
  return inverse;
}

// `p` as a line (or lines) of `format`; a tum line stamped `stamp`.
std::string poseText(const QuaternionPose& p, const std::string& format, double stamp) {
  std::ostringstream s;
  s.precision(17);
  if (format == "tum") s << stamp << ' ';
  if (format == "quaternion" || format == "tum") {
    s << p.t[0] << ' ' << p.t[1] << ' ' << p.t[2] << ' ' << p.q[0] << ' ' << p.q[1] << ' ' << p.q[2] << ' ' << p.q[3]
      << '\n';
    return s.str();
  }
  const std::array<double, 9> r = rotationOf(p.q);
  for (std::size_t i = 0; i < 3; ++i)
    s << r[3 * i] << ' ' << r[3 * i + 1] << ' ' << r[3 * i + 2] << ' ' << p.t[i] << (format == "kitti" ? ' ' : '\n');
  s << (format == "kitti" ? "\n" : "0 0 0 1\n");
  return s.str();
}

// `text`, written to `file` and read by --intrinsics, imports the scans the flags of `by_hand` did.
void requireReadAs(const std::string& frames_and_poses, const fs::path& file, const std::string& text,
                   const fs::path& by_hand) {
  std::ofstream(file, std::ios::binary) << text;
  const fs::path out = file.parent_path() / ("from-" + file.stem().string());
  const auto r = importWith(frames_and_poses, "--intrinsics " + file.string(), out);
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  requireSameScans(out, by_hand);
}

}  // namespace

TEST_CASE("a pose file read in the wrong format names the --pose-format that reads it") {
  const fs::path dir = test::scratch("import-checks-format");
  writeDepth(dir / "d.pgm", 2000, 0);
  std::ofstream(dir / "matrix.txt") << matrixPose(1, 2, 3);
  std::ofstream(dir / "one-line.txt") << "1 0 0 1 0 1 0 2 0 0 1 3 0 0 0 1\n";
  std::ofstream(dir / "kitti.txt") << "1 0 0 1 0 1 0 2 0 0 1 3\n";
  std::ofstream(dir / "no-stamp.txt") << "1 2 3 0 0 0 1\n";
  const std::string image = (dir / "d.pgm").string();
  for (const auto& [file, format, hint] : {std::tuple{"matrix.txt", "", "--pose-format matrix"},
                                           std::tuple{"one-line.txt", "", "--pose-format matrix"},
                                           std::tuple{"kitti.txt", "", "--pose-format kitti"},
                                           std::tuple{"no-stamp.txt", " --pose-format tum", "--pose-format quaternion"}}) {
    const auto r = importDepth(image, (dir / file).string(), format, dir / "ds");
    INFO(file << ": " << r.output);
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.output, Contains((dir / file).string() + ": line 1: "));
    CHECK_THAT(r.output, Contains(hint));
    CHECK_FALSE(fs::exists(dir / "ds"));
  }
}

TEST_CASE("poses one file per frame, in image order, import as one file of all the poses does") {
  const fs::path dir = test::scratch("import-checks-per-frame");
  std::string images, pose_files, all_poses;
  for (int f = 0; f < 3; ++f) {
    const std::string frame = "frame-00000" + std::to_string(f);
    writeDepth(dir / (frame + ".depth.pgm"), std::uint16_t(1500 + 100 * f), f);
    std::ofstream(dir / (frame + ".pose.txt")) << matrixPose(0.5 * f, -f, 2 + f);
    all_poses += matrixPose(0.5 * f, -f, 2 + f);
    images += " " + (dir / (frame + ".depth.pgm")).string();
    pose_files += " " + (dir / (frame + ".pose.txt")).string();
  }
  std::ofstream(dir / "all.txt") << all_poses;
  const auto per_frame = importDepth(images, pose_files, " --pose-format matrix", dir / "per-frame");
  INFO(per_frame.output);
  REQUIRE(per_frame.exit_code == 0);
  REQUIRE(importDepth(images, (dir / "all.txt").string(), " --pose-format matrix", dir / "one-file").exit_code == 0);
  requireSameScans(dir / "per-frame", dir / "one-file");
  CHECK(readDataset(dir / "per-frame").scans[2].origin == octomap::point3d(1.0f, -2.0f, 4.0f));

  // Two pose files for three images; a frame's file of two poses.
  auto r = importDepth(images, (dir / "frame-000000.pose.txt").string() + " " + (dir / "all.txt").string(),
                       " --pose-format matrix", dir / "bad");
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.output, Contains("2 pose files for 3 depth images"));
  std::ofstream(dir / "two.txt") << matrixPose(0, 0, 0) << matrixPose(1, 1, 1);
  r = importDepth(images, (dir / "two.txt").string() + " " + (dir / "frame-000001.pose.txt").string() + " " +
                              (dir / "frame-000002.pose.txt").string(),
                  " --pose-format matrix", dir / "bad");
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.output, Contains("two.txt: holds 2 poses: with one pose file per depth image, each holds its depth "
                                "image's pose alone"));
  CHECK_FALSE(fs::exists(dir / "bad"));
}

TEST_CASE("a TUM trajectory of more poses than images is matched by the images' timestamps, as associate.py does") {
  const fs::path dir = test::scratch("import-checks-tum");
  // Ground truth at 100 Hz from t = 100.000 s: pose i at x = i / 10.
  std::string trajectory;
  for (int i = 0; i <= 40; ++i) {
    std::ostringstream line;
    line.precision(17);
    line << 100.0 + 0.01 * i << ' ' << 0.1 * i << " 0 1 0 0 0 1\n";
    trajectory += line.str();
  }
  std::ofstream(dir / "groundtruth.txt") << trajectory;
  // Depth images at about 30 Hz, named by their timestamps; the nearest poses are 3, 17 and 31.
  const std::vector<std::pair<std::string, int>> frames = {{"100.031", 3}, {"100.1672", 17}, {"100.3088", 31}};
  std::string images, matched;
  for (std::size_t f = 0; f < frames.size(); ++f) {
    writeDepth(dir / (frames[f].first + ".pgm"), 2500, int(f));
    images += " " + (dir / (frames[f].first + ".pgm")).string();
    std::ostringstream line;
    line << frames[f].first << ' ' << 0.1 * frames[f].second << " 0 1 0 0 0 1\n";
    matched += line.str();
  }
  std::ofstream(dir / "matched.txt") << matched;
  const auto r = importDepth(images, (dir / "groundtruth.txt").string(), " --pose-format tum", dir / "associated");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  REQUIRE(importDepth(images, (dir / "matched.txt").string(), " --pose-format tum", dir / "by-hand").exit_code == 0);
  requireSameScans(dir / "associated", dir / "by-hand");

  // An image 0.05 s past the trajectory's end has no pose within 0.02 s.
  writeDepth(dir / "100.45.pgm", 2500, 0);
  auto bad = importDepth(images + " " + (dir / "100.45.pgm").string(), (dir / "groundtruth.txt").string(),
                         " --pose-format tum", dir / "bad");
  CHECK(bad.exit_code == 2);
  CHECK_THAT(bad.output, Contains("no pose within 0.02 s of 100.45.pgm (the nearest is 0.05 s away)"));
  // Images without timestamps, and more poses than images: the fix is named.
  writeDepth(dir / "a.pgm", 2500, 0);
  bad = importDepth((dir / "a.pgm").string(), (dir / "groundtruth.txt").string(), " --pose-format tum", dir / "bad");
  CHECK(bad.exit_code == 2);
  CHECK_THAT(bad.output, Contains("holds 41 poses for 1 depth images: one pose per depth image needed. A whole "
                                  "sequence's poses?"));
  CHECK_THAT(bad.output, Contains("--pose-start K --pose-step N"));
  CHECK_FALSE(fs::exists(dir / "bad"));
}

// docs/import.md, "Poses": frame i takes pose K + i N of a whole sequence's file.
TEST_CASE("import takes the images' poses out of a whole sequence's pose file by --pose-start and --pose-step") {
  const fs::path dir = test::scratch("import-checks-pose-step");
  std::string sequence;  // ten poses, pose p at (p, 0, 2)
  for (int p = 0; p < 10; ++p) sequence += matrixPose(p, 0, 2);
  std::ofstream(dir / "sequence.txt") << sequence;
  std::string images, chosen;  // every third image from the second: poses 1, 4, 7
  for (int f = 0; f < 3; ++f) {
    writeDepth(dir / (std::to_string(f) + ".pgm"), 2000, f);
    images += " " + (dir / (std::to_string(f) + ".pgm")).string();
    chosen += matrixPose(1 + 3 * f, 0, 2);
  }
  std::ofstream(dir / "chosen.txt") << chosen;
  const auto r = importDepth(images, (dir / "sequence.txt").string(), " --pose-format matrix --pose-start 1 "
                             "--pose-step 3", dir / "stepped");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  REQUIRE(importDepth(images, (dir / "chosen.txt").string(), " --pose-format matrix", dir / "by-hand").exit_code == 0);
  requireSameScans(dir / "stepped", dir / "by-hand");
  CHECK(readDataset(dir / "stepped").scans[2].origin == octomap::point3d(7.0f, 0.0f, 2.0f));

  // Past the file's end: refused, naming the pose the last image would take.
  auto bad = importDepth(images, (dir / "sequence.txt").string(), " --pose-format matrix --pose-start 2 "
                         "--pose-step 4", dir / "bad");
  CHECK(bad.exit_code == 2);
  CHECK_THAT(bad.output, Contains("sequence.txt: holds 10 poses: --pose-start 2 --pose-step 4 takes pose 10 (counting "
                                  "from 0) for the last of 3 depth images"));
  // A step of 0 is refused as a flag.
  bad = importDepth(images, (dir / "sequence.txt").string(), " --pose-format matrix --pose-step 0", dir / "bad");
  CHECK(bad.exit_code == 2);
  CHECK_THAT(bad.output, Contains("--pose-step: Value 0 not in range 1 to 1000000"));
  // One file per frame already pairs each image with its pose.
  std::ofstream(dir / "p0.txt") << matrixPose(0, 0, 2);
  std::ofstream(dir / "p1.txt") << matrixPose(1, 0, 2);
  std::ofstream(dir / "p2.txt") << matrixPose(2, 0, 2);
  bad = importDepth(images, (dir / "p0.txt").string() + " " + (dir / "p1.txt").string() + " " +
                                (dir / "p2.txt").string(), " --pose-format matrix --pose-start 1", dir / "bad");
  CHECK(bad.exit_code == 2);
  CHECK_THAT(bad.output, Contains("--pose-start and --pose-step take poses out of one file of a whole sequence, not "
                                  "out of 3 pose files"));
  CHECK_FALSE(fs::exists(dir / "bad"));

  // A TUM trajectory is taken by position when asked, even where the images' names are numbers (0.pgm ...).
  std::string tum;
  for (int p = 0; p < 10; ++p) tum += std::to_string(100 + p) + ".5 " + std::to_string(p) + " 0 2 0 0 0 1\n";
  std::ofstream(dir / "tum.txt") << tum;
  const auto by_position = importDepth(images, (dir / "tum.txt").string(), " --pose-format tum --pose-start 1 "
                                       "--pose-step 3", dir / "tum-stepped");
  INFO(by_position.output);
  REQUIRE(by_position.exit_code == 0);
  requireSameScans(dir / "tum-stepped", dir / "by-hand");
  const Dataset stepped = readDataset(dir / "stepped");
  CHECK(stepped.source.at("pose_start_step") == nlohmann::json::array({1, 3}));
  // Without --poses (import cloud may go without), the flags are refused.
  std::ofstream(dir / "c.xyz") << "1 2 3\n";
  bad = test::runCli("import cloud " + (dir / "c.xyz").string() + " --pose-start 1 --out " + (dir / "bad").string());
  CHECK(bad.exit_code == 2);
  CHECK_THAT(bad.output, Contains("--pose-start requires --poses"));
  CHECK_FALSE(fs::exists(dir / "bad"));
}

TEST_CASE("import depth prints the median depth after --depth-scale and warns when no depth camera measures it") {
  const fs::path dir = test::scratch("import-checks-depth-scale");
  // Three frames: 11 pixels at 3000 and one at 3001 + frame: the median raw value is 3000.
  std::string images, poses;
  for (int f = 0; f < 3; ++f) {
    writeDepth(dir / ("d" + std::to_string(f) + ".pgm"), 3000, f);
    images += " " + (dir / ("d" + std::to_string(f) + ".pgm")).string();
    poses += "0 0 0 0 0 0 1\n";
  }
  std::ofstream(dir / "poses.txt") << poses;
  const std::string pose_file = (dir / "poses.txt").string();
  for (const auto& [scale, median, warned] : {std::tuple{"1000", "3 m", false}, std::tuple{"5000", "0.6 m", false},
                                              std::tuple{"200", "15 m", true}, std::tuple{"100000", "0.03 m", true}}) {
    const auto r = importDepth(images, pose_file, std::string(" --force --depth-scale ") + scale, dir / "ds");
    INFO("--depth-scale " << scale << ": " << r.output);
    REQUIRE(r.exit_code == 0);
    CHECK_THAT(r.output, Contains(std::string("median depth ") + median + " (raw value / --depth-scale " + scale + ")"));
    CHECK((r.output.find("warning: a median depth of") != std::string::npos) == warned);
    if (warned) CHECK_THAT(r.output, Contains(std::string("is --depth-scale ") + scale + " right?"));
  }
}

TEST_CASE("the median depth is the median of a sample spread over every image, not of its first pixels") {
  // Two 1200 x 1000 images (past the million-pixel sample, so every other pixel is read), raw values spread evenly
  // over 1000-5000 in a scrambled order: the median is 3000 raw, 3 m at --depth-scale 1000; the smallest and the
  // most common value are not.
  const fs::path dir = test::scratch("import-checks-median");
  constexpr int kW = 1200, kH = 1000;
  std::string images, poses;
  for (int f = 0; f < 2; ++f) {
    std::string body;
    body.reserve(std::size_t(kW) * kH * 2);
    for (std::uint64_t i = 0; i < std::uint64_t(kW) * kH; ++i) {
      const auto v = std::uint16_t(1000 + (i * 7919 + std::uint64_t(f)) % 4001);
      body += char(v >> 8), body += char(v & 0xff);
    }
    const fs::path image = dir / ("big" + std::to_string(f) + ".pgm");
    std::ofstream(image, std::ios::binary) << "P5\n" << kW << ' ' << kH << "\n65535\n" << body;
    images += " " + image.string();
    poses += "0 0 0 0 0 0 1\n";
  }
  std::ofstream(dir / "poses.txt") << poses;
  const auto r = importDepth(images, (dir / "poses.txt").string(), " --stride 50", dir / "ds");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  std::smatch m;
  REQUIRE(std::regex_search(r.output, m, std::regex("median depth ([0-9.]+) m")));
  CHECK(std::stod(m[1].str()) == Approx(3.0).margin(0.002));
}

TEST_CASE("import names the order when --poses comes before the images, and a TUM file matches by timestamp even at "
          "equal counts") {
  const fs::path dir = test::scratch("import-checks-order");
  writeDepth(dir / "d.pgm", 2000, 0);
  std::ofstream(dir / "p.txt") << "0 0 0 0 0 0 1\n";
  auto r = test::runCli("import depth --poses " + (dir / "p.txt").string() + " " + (dir / "d.pgm").string() +
                        kCamera + " --out " + (dir / "ds").string());
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.output, Contains("no depth images given: --poses takes every file up to the next option, so give the "
                                "depth images before --poses"));
  // As many poses as images, but years away from them: refused, not paired in order.
  writeDepth(dir / "1305031102.160407.pgm", 2000, 0);
  std::ofstream(dir / "far.txt") << "1400000000.0 7 0 0 0 0 0 1\n";
  r = importDepth((dir / "1305031102.160407.pgm").string(), (dir / "far.txt").string(), " --pose-format tum",
                  dir / "ds");
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.output, Contains("no pose within 0.02 s of 1305031102.160407.pgm"));
  CHECK_FALSE(fs::exists(dir / "ds"));
}

// docs/import.md, "Poses": --pose-convention world-to-camera inverts each pose, [R^T | -R^T t], whatever its format.
TEST_CASE("import with --pose-convention world-to-camera reads every pose format's world-to-camera poses as their "
          "camera-to-world inverses, for depth images and clouds") {
  const fs::path dir = test::scratch("import-checks-convention");
  const double half = std::sin(0.4) / 3;  // 0.8 rad about the axis (1, 2, 2) / 3
  const std::vector<QuaternionPose> poses{{{half, 2 * half, 2 * half, std::cos(0.4)}, {0.5, -0.2, 1}},
                                          {{0, 0, std::sin(1.1), std::cos(1.1)}, {-1, 0.4, 2}}};
  std::string images, clouds;
  for (int f = 0; f < 2; ++f) {
    images += writeFramePng(dir / ("depth" + std::to_string(f) + ".png"), f).string() + " ";
    std::ofstream(dir / ("cloud" + std::to_string(f) + ".xyz")) << "0.1 0.2 1\n-0.3 0.1 2.5\n" << f << " 1 0\n";
    clouds += (dir / ("cloud" + std::to_string(f) + ".xyz")).string() + " ";
  }
  for (const std::string format : {"quaternion", "tum", "matrix", "kitti"}) {
    std::ofstream camera_to_world(dir / (format + "-c2w.txt")), world_to_camera(dir / (format + "-w2c.txt"));
    for (std::size_t f = 0; f < poses.size(); ++f) {
      camera_to_world << poseText(poses[f], format, 100.0 + double(f));
      world_to_camera << poseText(worldToCamera(poses[f]), format, 100.0 + double(f));
    }
    camera_to_world.close(), world_to_camera.close();
    for (const std::string& command : {"import depth " + images + kCamera, "import cloud " + clouds}) {
      INFO(format << ", " << command.substr(0, 12));
      const std::string posed = command + " --pose-format " + format + " --poses " + dir.string() + "/" + format;
      fs::remove_all(dir / "right"), fs::remove_all(dir / "read");
      REQUIRE(test::runCli(posed + "-c2w.txt --out " + (dir / "right").string()).exit_code == 0);
      const auto r =
          test::runCli(posed + "-w2c.txt --pose-convention world-to-camera --out " + (dir / "read").string());
      INFO(r.output);
      REQUIRE(r.exit_code == 0);
      requireSameScans(dir / "right", dir / "read", 1e-5);
      CHECK(readDataset(dir / "read").source.at("pose_convention") == "world-to-camera");
    }
  }
  const auto bad = test::runCli("import cloud " + clouds + " --poses " + (dir / "matrix-c2w.txt").string() +
                                " --pose-format matrix --pose-convention sensor-to-world --out " +
                                (dir / "bad").string());
  CHECK(bad.exit_code == 2);
  CHECK_THAT(bad.output, Contains("--pose-convention: sensor-to-world not in {camera-to-world,world-to-camera}"));
  CHECK_FALSE(fs::exists(dir / "bad"));
}

// docs/import.md, "Intrinsics files": the files of 3DMatch (7-Scenes) and Replica, read as downloaded.
TEST_CASE("import depth --intrinsics reads 3DMatch's camera-intrinsics.txt and Replica's cam_params.json as the flags "
          "they hold") {
  const fs::path dir = test::scratch("import-checks-intrinsics");
  std::string frames = " ";
  for (int f = 0; f < 3; ++f)
    frames += writeFramePng(dir / ("frame-00000" + std::to_string(f) + ".depth.png"), f).string() + " ";
  std::ofstream(dir / "poses.txt") << matrixPose(0, 0, 1) << matrixPose(0.5, 0, 1) << matrixPose(1, 0.2, 1);
  const std::string posed = frames + "--poses " + (dir / "poses.txt").string() + " --pose-format matrix";
  // As numpy.savetxt writes 3DMatch's file: tab-separated, in scientific notation.
  std::ofstream(dir / "camera-intrinsics.txt") << "5.703422241210937500e+00\t0.000000000000000000e+00\t3.5e+00\n"
                                                  "0.0e+00\t5.703422241210937500e+00\t2.5e+00\n0\t0\t1\n";
  auto r = importWith(posed, "--intrinsics " + (dir / "camera-intrinsics.txt").string(), dir / "from-file");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  REQUIRE(importWith(posed, "--fx 5.7034222412109375 --fy 5.7034222412109375 --cx 3.5 --cy 2.5", dir / "by-hand")
              .exit_code == 0);
  requireSameScans(dir / "from-file", dir / "by-hand");
  CHECK(readDataset(dir / "from-file").source.at("intrinsics_file") == "camera-intrinsics.txt");

  // Replica's cam_params.json: its scale is the depth scale (6553.5), and the images must be its size.
  std::ofstream(dir / "cam_params.json")
      << R"({"camera": {"w": 8, "h": 6, "fx": 6.0, "fy": 6.5, "cx": 3.5, "cy": 2.0, "scale": 6553.5}})";
  r = importWith(posed, "--intrinsics " + (dir / "cam_params.json").string(), dir / "replica");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  REQUIRE(importWith(posed, "--depth-scale 6553.5 --fx 6 --fy 6.5 --cx 3.5 --cy 2", dir / "replica-by-hand")
              .exit_code == 0);
  requireSameScans(dir / "replica", dir / "replica-by-hand");
  CHECK(readDataset(dir / "replica").source.at("depth_scale") == 6553.5);
  // Without "scale" the file is read when --depth-scale gives it (docs/import.md: refused otherwise).
  requireReadAs(posed + " --depth-scale 6553.5", dir / "no-scale.json",
                R"({"camera": {"w": 8, "h": 6, "fx": 6.0, "fy": 6.5, "cx": 3.5, "cy": 2.0}})", dir / "replica-by-hand");
  // A UTF-8 byte order mark before the numbers, as Windows editors save text, is skipped.
  requireReadAs(posed, dir / "bom.txt",
                "\xEF\xBB\xBF" "5.703422241210937500e+00 0 3.5\n0 5.703422241210937500e+00 2.5\n0 0 1\n",
                dir / "by-hand");
  // numpy's round-off in a computed matrix (1e-17 for a 0, 1.0000000000000002 for the 1) is the same camera.
  requireReadAs(posed, dir / "round-off.txt",
                "5.703422241210937500e+00 1e-17 3.5\n0 5.703422241210937500e+00 2.5\n-2e-17 0 1.0000000000000002\n",
                dir / "by-hand");
}

TEST_CASE("a bad intrinsics file, or no intrinsics, is refused naming the file, the line or field and the fix") {
  const fs::path dir = test::scratch("import-checks-intrinsics-bad");
  const fs::path frame = writeFramePng(dir / "depth000000.png", 0);
  std::ofstream(dir / "pose.txt") << matrixPose(0, 0, 1);
  const std::string posed = frame.string() + " --poses " + (dir / "pose.txt").string() + " --pose-format matrix";
  std::ofstream(dir / "skewed.txt") << "6 0.5 3.5\n0 6 2.5\n0 0 1\n";
  std::ofstream(dir / "four.txt") << matrixPose(6, 3.5, 2.5);  // a 4x4, 16 numbers
  std::ofstream(dir / "no-fy.json") << R"({"camera": {"fx": 6, "cx": 3.5, "cy": 2.5}})";
  std::ofstream(dir / "projective.txt") << "6 0 3.5\n0 6 2.5\n0 1e-6 1\n";  // past round-off: shown as it is
  std::ofstream(dir / "word.txt") << "6 0 3.5\n0 6 2.5\n0 0 1 hello\n";
  std::ofstream(dir / "array.json") << "[[6, 0, 3.5], [0, 6, 2.5], [0, 0, 1]]";
  std::ofstream(dir / "no-scale.json") << R"({"camera": {"fx": 6, "fy": 6, "cx": 3.5, "cy": 2.5}})";
  std::ofstream(dir / "big.json") << R"({"camera": {"w": 1200, "h": 680, "fx": 600, "fy": 600, "cx": 599.5,
                                       "cy": 339.5, "scale": 6553.5}})";
  const std::string at = posed + " --intrinsics " + dir.string() + "/", file = dir.string() + "/";
  requireRefused({{at + "skewed.txt", file + "skewed.txt: row 1, column 2: is 0.5, expected 0: a camera matrix "
                                             "is fx 0 cx / 0 fy cy / 0 0 1"},
                  {at + "projective.txt", file + "projective.txt: row 3, column 2: is 1e-06, expected 0"},
                  {at + "four.txt", file + "four.txt: line 3: more than 9 numbers"},
                  {at + "word.txt", file + "word.txt: line 3: column 4 (matrix entry) is \"hello\": not a "
                                           "number"},
                  {at + "array.json", file + "array.json: is a JSON array, not an intrinsics file: give "
                                             "{\"camera\": {\"w\", \"h\", \"fx\", \"fy\", \"cx\", \"cy\", \"scale\"}} "
                                             "(Replica's "
                                             "cam_params.json) or text of 9 numbers"},
                  {at + "no-fy.json", file + "no-fy.json: camera.fy: missing"},
                  {at + "no-scale.json", file + "no-scale.json: camera.scale: missing: give the raw depth units per "
                                                "metre (Replica's is 6553.5), or --depth-scale"},
                  {at + "big.json", frame.string() + ": is 8x6 pixels, but --intrinsics " + file +
                                        "big.json is for 1200x680 images"},
                  {at + "skewed.txt --fx 6", "--intrinsics excludes --fx"},
                  {posed + " --fx 6 --fy 6 --cx 3.5",
                   "the camera's intrinsics have no default: give --intrinsics FILE (3DMatch's camera-intrinsics.txt, "
                   "Replica's cam_params.json) or all of --fx --fy --cx --cy"}},
                 dir / "ds");
}

// docs/import.md, "Intrinsics files": what the file's own rules refuse, one rule a case.
namespace {

// `text` as the intrinsics file `name` of a one-frame import, refused naming the file, then `message`.
void requireIntrinsicsRefused(const std::string& dir_name, const std::string& name, const std::string& text,
                              const std::string& message) {
  const fs::path dir = test::scratch(dir_name);
  const fs::path frame = writeFramePng(dir / "depth000000.png", 0);
  std::ofstream(dir / "pose.txt") << matrixPose(0, 0, 1);
  std::ofstream(dir / name) << text;
  requireRefused({{frame.string() + " --poses " + (dir / "pose.txt").string() + " --pose-format matrix --intrinsics " +
                       (dir / name).string(),
                   (dir / name).string() + ": " + message}},
                 dir / "ds");
}

}  // namespace

TEST_CASE("an intrinsics file whose principal point lies outside its images' width or height is refused") {
  requireIntrinsicsRefused("intrinsics-cx-outside", "cam_params.json",
                           R"({"camera": {"w": 8, "h": 6, "fx": 6, "fy": 6, "cx": 599.5, "cy": 2.5, "scale": 1000}})",
                           "camera.cx: is 599.5, outside the image's 0 to 8 pixels (camera.w)");
  requireIntrinsicsRefused("intrinsics-cy-outside", "cam_params.json",
                           R"({"camera": {"w": 8, "h": 6, "fx": 6, "fy": 6, "cx": 3.5, "cy": -1, "scale": 1000}})",
                           "camera.cy: is -1, outside the image's 0 to 6 pixels (camera.h)");
}

TEST_CASE("Replica's cam_params.json without w or h is refused, naming the field") {
  requireIntrinsicsRefused("intrinsics-no-w", "cam_params.json",
                           R"({"camera": {"h": 6, "fx": 6, "fy": 6, "cx": 3.5, "cy": 2.5, "scale": 1000}})",
                           "camera.w: missing: give the images' width in pixels");
  requireIntrinsicsRefused("intrinsics-no-h", "cam_params.json",
                           R"({"camera": {"w": 8, "fx": 6, "fy": 6, "cx": 3.5, "cy": 2.5, "scale": 1000}})",
                           "camera.h: missing: give the images' height in pixels");
}

TEST_CASE("a number beyond a double's range in an intrinsics file is refused as out of range, not as not a number") {
  requireIntrinsicsRefused("intrinsics-1e400", "camera-intrinsics.txt", "1e400 0 3.5\n0 6 2.5\n0 0 1\n",
                           "line 1: column 1 (matrix entry) is \"1e400\": out of a double's range");
}

TEST_CASE("a # comment after the numbers of a camera-intrinsics.txt line is refused, saying a comment takes a whole "
          "line") {
  requireIntrinsicsRefused("intrinsics-comment", "camera-intrinsics.txt", "6 0 3.5 # fx 0 cx\n0 6 2.5\n0 0 1\n",
                           "line 1: column 4 is \"#\", a comment after the numbers: a # comment takes a whole line "
                           "(as numpy.savetxt writes one); move it to a line of its own");
}

// docs/import.md, "Poses": Replica's results/depthNNNNNN.png take line NNNNNN of the whole traj.txt.
TEST_CASE("frames take the poses of a whole trajectory by the numbers in their names (--pose-by-frame-number)") {
  const fs::path dir = test::scratch("import-checks-frame-number");
  std::string trajectory;  // 300 poses, 16 numbers a line as Replica's traj.txt; pose p at (p / 100, 0, 2)
  for (int p = 0; p < 300; ++p) {
    std::string pose = matrixPose(p / 100.0, 0, 2);
    std::replace(pose.begin(), pose.end(), '\n', ' ');
    trajectory += pose + "\n";
  }
  std::ofstream(dir / "traj.txt") << trajectory;
  std::string frames, chosen;
  for (const int number : {0, 100, 250}) {
    const std::string name = "depth000" + std::string(number == 0 ? "000" : std::to_string(number)) + ".png";
    frames += writeFramePng(dir / name, number / 100).string() + " ";
    chosen += matrixPose(number / 100.0, 0, 2);
  }
  std::ofstream(dir / "chosen.txt") << chosen;
  const std::string camera = " --pose-format matrix --fx 6 --fy 6 --cx 3.5 --cy 2.5";
  const auto r = importWith(frames + "--poses " + (dir / "traj.txt").string(), "--pose-by-frame-number" + camera,
                            dir / "numbered");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  REQUIRE(importWith(frames + "--poses " + (dir / "chosen.txt").string(), camera, dir / "by-hand").exit_code == 0);
  requireSameScans(dir / "numbered", dir / "by-hand");
  const Dataset numbered = readDataset(dir / "numbered");
  CHECK(numbered.scans[2].origin == octomap::point3d(2.5f, 0.0f, 2.0f));
  CHECK(numbered.source.at("pose_by_frame_number") == true);

  // A number past the trajectory, a name without one or with two or with one past 2^64, two names of one number,
  // another selection, one pose file per frame: refused.
  const std::string past = writeFramePng(dir / "depth000300.png", 3).string();
  const std::string unnumbered = writeFramePng(dir / "last.png", 3).string();
  const std::string two_numbers = writeFramePng(dir / "depth000005-cam2.png", 0).string();
  const std::string huge = writeFramePng(dir / "depth99999999999999999999999.png", 0).string();
  const std::string ten = writeFramePng(dir / "depth10.png", 0).string();
  const std::string ten_again = writeFramePng(dir / "depth010.png", 0).string();
  const std::string traj = " --poses " + (dir / "traj.txt").string() + " --pose-by-frame-number" + camera;
  const std::string chosen_twice = " --poses " + (dir / "chosen.txt").string() + " " + (dir / "chosen.txt").string();
  requireRefused({{past + traj, (dir / "traj.txt").string() + ": holds 300 poses (numbered 0 to 299): "
                                                              "depth000300.png takes pose 300"},
                  {unnumbered + traj, unnumbered + ": --pose-by-frame-number takes the pose numbered by the one "
                                                   "number in each depth image's file name (depth000120.png: pose "
                                                   "120), and this name has no number"},
                  {two_numbers + traj, two_numbers + ": --pose-by-frame-number takes the pose numbered by the one "
                                                     "number in each depth image's file name (depth000120.png: pose "
                                                     "120), and this name has more than one"},
                  {huge + traj, huge + ": --pose-by-frame-number takes the pose numbered by the one number in each "
                                       "depth image's file name (depth000120.png: pose 120), and this name has one "
                                       "too large for a pose number: 99999999999999999999999"},
                  {ten + " " + ten_again + traj, ten_again + ": is frame 10, as " + ten + " is"},
                  {past + traj + " --pose-step 2", "--pose-step excludes --pose-by-frame-number"},
                  {past + " " + unnumbered + chosen_twice + " --pose-by-frame-number" + camera,
                   "--pose-by-frame-number takes poses out of one file of a whole sequence, not out of 2 pose files"}},
                 dir / "bad");
}

// TUM's associate.py pairs the closest (image, pose) first and uses each pose once.
TEST_CASE("two images nearest the same TUM pose take two poses, as associate.py pairs them") {
  const fs::path dir = test::scratch("import-checks-associate");
  // Poses at 50 Hz; both images are nearest the pose at 100.005 s, the image at 100.000 s more so: the image at
  // 100.012 s takes the next pose, 0.013 s away.
  std::ofstream(dir / "groundtruth.txt") << "100.005 0 0 1 0 0 0 1\n100.025 1 0 1 0 0 0 1\n100.045 2 0 1 0 0 0 1\n";
  std::ofstream(dir / "matched.txt") << "100.000 0 0 1 0 0 0 1\n100.012 1 0 1 0 0 0 1\n";
  const std::string images = writeFramePng(dir / "100.000.png", 0).string() + " " +
                             writeFramePng(dir / "100.012.png", 1).string();
  const std::string camera = " --pose-format tum --fx 6 --fy 6 --cx 3.5 --cy 2.5";
  const auto r = importWith(images + " --poses " + (dir / "groundtruth.txt").string(), camera, dir / "associated");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  REQUIRE(importWith(images + " --poses " + (dir / "matched.txt").string(), camera, dir / "by-hand").exit_code == 0);
  requireSameScans(dir / "associated", dir / "by-hand");

  // Three images within 0.02 s of two poses: the one left without a pose is refused, named.
  const std::string third = writeFramePng(dir / "100.030.png", 2).string();
  std::ofstream(dir / "two.txt") << "100.005 0 0 1 0 0 0 1\n100.025 1 0 1 0 0 0 1\n";
  const auto bad = importWith(images + " " + third + " --poses " + (dir / "two.txt").string(), camera, dir / "bad");
  CHECK(bad.exit_code == 2);
  CHECK_THAT(bad.output, Contains("two.txt: every pose within 0.02 s of 100.012.png is paired with an image nearer to "
                                  "it in time"));
  CHECK_FALSE(fs::exists(dir / "bad"));
}
