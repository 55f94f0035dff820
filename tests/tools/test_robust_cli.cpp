// Errors a user can act on, real pose formats, data-set paths and logs (docs/robustness.md, "Messages,
// formats and the cluster"). Every case runs the real command; OCCSWEEP_TEST_CLI=/path/to/old/occsweep runs them
// against another build.
#include <catch2/catch.hpp>

#include <fstream>

#include <nlohmann/json.hpp>

#include "cli_help.hpp"
#include "occsweep/io/control_characters.hpp"
#include "occsweep/eval/dataset.hpp"
#include "robust_cli_helpers.hpp"

using namespace occsweep;
namespace fs = std::filesystem;
using Catch::Matchers::Contains;

namespace {

/// A small built-in scene, written once per test program.
fs::path tinyScene() {
  static const fs::path dir = [] {
    const fs::path d = test::processScratch("robust-cli-scene") / "scene";
    const auto r = test::runCli("scene --out " + d.string() + " --scans 4 --width 24 --height 12");
    REQUIRE(r.exit_code == 0);
    return d;
  }();
  return dir;
}

void copyDataset(const fs::path& from, const fs::path& to) {
  fs::create_directories(to);
  fs::copy(from, to, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
}

nlohmann::json readJsonFile(const fs::path& f) { return nlohmann::json::parse(std::ifstream(f)); }
void writeJsonFile(const fs::path& f, const nlohmann::json& j) { std::ofstream(f) << j.dump(1); }

/// A usage error: exit 2, the message on the line, no CLI11 default (its 309-digit maximum of double), nothing
/// written into `dir`.
void requireUsageError(const std::string& args, const std::string& message, const fs::path& dir) {
  INFO("occsweep " << args);
  const auto before = test::listing(dir);
  const auto r = test::run(args);
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.output, Contains(message));
  CHECK_THAT(r.output, !Contains("179769313486"));
  CHECK_THAT(r.output, !Contains("not in range"));
  CHECK(test::listing(dir) == before);
}

}  // namespace

TEST_CASE("numeric flags are refused with their rule in plain numbers, exit 2, nothing written") {
  const fs::path dir = test::scratch("robust-cli-numbers");
  const std::string ds = tinyScene().string(), out = (dir / "m.ot").string();
  requireUsageError("map --dataset " + ds + " --k 0 --out " + out, "--k must be an integer from 1 to 100000, got 0", dir);
  requireUsageError("map --dataset " + ds + " --k 1.5 --out " + out, "--k must be an integer from 1 to 100000, got 1.5", dir);
  requireUsageError("map --dataset " + ds + " --k 99999999999 --out " + out,
                    "--k must be an integer from 1 to 100000, got 99999999999", dir);
  requireUsageError("map --dataset " + ds + " --s-c 0 --out " + out, "--s-c must be a number > 0, got 0", dir);
  requireUsageError("map --dataset " + ds + " --resolution 0 --out " + out, "--resolution must be a number > 0, got 0",
                    dir);
  requireUsageError("map --dataset " + ds + " --p-m abc --out " + out, "--p-m must be a number in [0, 0.5], got abc", dir);
  requireUsageError("map --dataset " + ds + " --p-h 1.5 --out " + out, "--p-h must be a number in [0.5, 1], got 1.5", dir);
  requireUsageError("map --dataset " + ds + " --p-t nan --out " + out, "--p-t must be a number in [0, 1], got nan", dir);
  requireUsageError("map --dataset " + ds + " --threads -1 --out " + out, "--threads must be an integer from 0 to 1024, got -1",
                    dir);
  requireUsageError("sweep --dataset " + ds + " --grid octomap-opt --threads -1 --out " + (dir / "s.json").string(),
                    "--threads must be an integer from 0 to 1024, got -1", dir);
  requireUsageError("scene --out " + (dir / "s").string() + " --scans 0", "--scans must be an integer from 1 to 100000, got 0",
                    dir);
  requireUsageError("scene --out " + (dir / "s").string() + " --seed abc", "--seed cannot take the value abc", dir);
  requireUsageError("grid count octomap-opt --groups 0", "--groups must be an integer >= 1, got 0", dir);
  requireUsageError("cluster run-local " + dir.string() + " --threads 0", "--threads must be an integer from 1 to 1024, got 0", dir);
}

TEST_CASE("a numeric flag's value that looks like an option (-inf, -nan) is read as its value and refused by its rule") {
  // Old binary: "unknown option -inf": the message's own walk of the line took the value for a flag, which CLI11 had
  // read as the value.
  const fs::path dir = test::scratch("robust-cli-minus-inf");
  const std::string ds = tinyScene().string(), out = (dir / "m.ot").string();
  for (const std::string value : {"-inf", "-nan", "-infinity", "-INF"})
    requireUsageError("results diff a.json b.json --auc-tolerance " + value,
                      "--auc-tolerance must be a number >= 0, got " + value, dir);
  requireUsageError("map --dataset " + ds + " --s-c -inf --out " + out, "--s-c must be a number > 0, got -inf", dir);
  requireUsageError("map --dataset " + ds + " --p-t -nan --out " + out, "--p-t must be a number in [0, 1], got -nan", dir);
  requireUsageError("scene --out " + (dir / "s").string() + " --noise -infinity",
                    "--noise must be a number in [0, 1000], got -infinity", dir);
  // An option after the value is still checked: a typo there is named.
  requireUsageError("results diff a.json b.json --auc-tolerance -inf --auc-onyl", "unknown option --auc-onyl", dir);
}

TEST_CASE("a typo in a command or an option is exit 2 with the nearest valid name") {
  const fs::path dir = test::scratch("robust-cli-typos");
  const std::string ds = tinyScene().string(), out = (dir / "m.ot").string();
  requireUsageError("mpa --dataset " + ds + " --out " + out, "unknown command 'mpa': did you mean map?", dir);
  requireUsageError("import clod a.xyz --out " + (dir / "x").string(), "unknown command 'clod': did you mean cloud?",
                    dir);
  requireUsageError("cluster run-locl " + dir.string(), "unknown command 'run-locl': did you mean run-local?", dir);
  requireUsageError("map --dataset " + ds + " --p_h 0.7 --out " + out, "unknown option --p_h: did you mean --p-h?", dir);
  requireUsageError("sweep --dataset " + ds + " --grid octomap-opt --thread 2 --out " + out,
                    "unknown option --thread: did you mean --threads?", dir);
  // Nothing near: the choices are listed instead of a guess.
  requireUsageError("zzzzzz", "unknown command 'zzzzzz' (commands: ", dir);
  // A missing subcommand names the choices; a missing option names itself.
  requireUsageError("grid", "a command is required: one of count, list, shards", dir);
  requireUsageError("map --dataset " + ds, "--out is required", dir);
}

// An unset shell variable (`--out "$OUT"`) gives an empty path: refused naming the flag, before anything is read or
// written (docs/robustness.md, "Messages, formats and the cluster").
TEST_CASE("an empty path (an unset shell variable) is refused naming its flag, for every command with an --out") {
  // Old binary: "filesystem error: cannot make absolute path" (scene, sweep, merge, import, results export,
  // reproduce), a refusal of the name's ending (map, plot), nothing written without a word (compare --csv ''), or
  // the output written into the current folder (cluster plan, dataset middlebury, dataset generate).
  const fs::path dir = test::scratch("robust-cli-empty-paths"), real = test::sourceTree() / "tests/data/real";
  copyDataset(tinyScene(), dir / "ds");
  std::ofstream(dir / "a.xyz") << "1 0 0\n0 1 0\n";
  std::ofstream(dir / "boxes.json") << R"({"boxes": [{"min": [-1, -1, 0], "max": [1, 1, 1]}]})";
  fs::create_directories(dir / "gen/pcs-0000");
  std::ofstream(dir / "gen/ranking.json") << R"({"format": "occsweep-pointcloud-ranking",
    "sets": [{"folder": "pcs-0000", "id": 0, "naive": {"fdr": 0.1, "tpr": 0.9}}]})";
  std::string images;
  for (int i = 1; i <= 5; ++i) images += " " + (real / "slambook_joinMap/depth" / (std::to_string(i) + ".pgm")).string();
  REQUIRE(test::runIn(dir, "sweep --dataset ds --grid octomap-opt --quiet --out r.json").exit_code == 0);
  const std::map<std::string, std::string> before_out = {
      {"cluster plan", "--experiment sweep --dataset ds --grid octomap-opt:1"},
      {"cluster select", "gen/ranking.json"},
      {"dataset generate", "--name parking-plain-I --pcs 0 --no-preview --quiet"},
      {"dataset middlebury", "--quiet"},
      {"import cloud", "a.xyz"},
      {"import depth", images + " --poses " + (real / "slambook_joinMap/pose.txt").string() +
                           " --fx 518 --fy 519 --cx 325.5 --cy 253.5"},
      {"import graph", (real / "octomap_share_data/spherical_scan.graph").string()},
      {"import truth", "boxes.json --dataset ds"},
      {"map", "--dataset ds"},
      {"merge", "r.json"},
      {"plot budget", "r.json"},
      {"plot curves", "r.json"},
      {"plot improvement", "r.json"},
      {"plot params", "r.json"},
      {"reproduce", "--scale ci --no-figures --quiet --name parking-plain-I --steps fits"},
      {"results export", "r.json"},
      {"scene", "--scans 2 --width 8 --height 6"},
      {"sweep", "--dataset ds --grid octomap-opt --quiet"}};
  auto requireRefused = [&dir](const std::string& args, const std::string& flag) {
    INFO("occsweep " << args);
    const auto before = test::listing(dir);
    const auto r = test::runIn(dir, args);  // in `dir`: what an empty path would put in the current folder shows
    INFO(r.output);
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.output, Contains(flag + " needs a path, got an empty value (an unset shell variable?)"));
    CHECK(test::listing(dir) == before);
  };
  std::map<std::string, test::LeafHelp> leaves;
  test::walkHelp("", leaves);
  std::size_t with_out = 0;
  for (const auto& [command, help] : leaves) {
    if (!help.flags.count("--out")) continue;
    ++with_out;
    INFO(command << " takes --out: give it its other arguments in this test");
    REQUIRE(before_out.count(command));
    requireRefused(command + " " + before_out.at(command) + " --out ''", "--out");
  }
  CHECK(with_out >= 14);
  // compare's tables and plot's data, and paths read.
  for (const std::string flag : {"--json", "--csv", "--markdown", "--latex"})
    requireRefused("compare r.json " + flag + " ''", flag);
  requireRefused("plot budget r.json --out b.png --json ''", "--json");
  requireRefused("map --dataset '' --out m.ot", "--dataset");
  requireRefused("results check ''", "file");
  requireRefused("compare r.json ''", "files");
}

TEST_CASE("help and version (--help, --version) still exit 0") {
  for (const std::string args : {"--help", "--version", "map --help", "import truth --help", "cluster run-local --help"}) {
    INFO(args);
    const auto r = test::run(args);
    CHECK(r.exit_code == 0);
    CHECK_THAT(r.output, !Contains("error"));
  }
}

TEST_CASE("a region without a voxel centre names the manifest and its field, and a sweep leaves nothing") {
  const fs::path dir = test::scratch("robust-cli-region");
  copyDataset(tinyScene(), dir / "ds");
  auto m = readJsonFile(dir / "ds" / "manifest.json");
  m["region"] = {{"min", {0.01, 0.01, 0.01}}, {"max", {0.02, 0.02, 0.02}}};  // centres at 0.05 + 0.1 i
  writeJsonFile(dir / "ds" / "manifest.json", m);
  auto r = test::run("map --dataset " + (dir / "ds").string() + " --out " + (dir / "m.ot").string());
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.output, Contains((dir / "ds" / "manifest.json").string() + ": region: the region holds no voxel centre"));
  CHECK_THAT(r.output, Contains("resolution 0.1"));
  CHECK_FALSE(fs::exists(dir / "m.ot"));
  CHECK_FALSE(fs::exists(dir / "m.ot.json"));
  const auto before = test::listing(dir);
  r = test::run("sweep --quiet --dataset " + (dir / "ds").string() + " --grid octomap-opt --out " +
                (dir / "s.json").string());
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.output, Contains("manifest.json: region: "));
  CHECK(test::listing(dir) == before);  // no results, no .partial.jsonl
}

TEST_CASE("a PLY header without end_header names the file and the 1 MiB header limit") {
  const fs::path dir = test::scratch("robust-cli-ply");
  {
    std::ofstream big(dir / "big.ply");
    big << "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n";
    const std::string comment = "comment " + std::string(1000, 'c') + "\n";
    for (int i = 0; i < 1100; ++i) big << comment;
    big << "end_header\n0 0 0\n";
  }
  auto r = test::run("import cloud " + (dir / "big.ply").string() + " --out " + (dir / "out").string());
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.output, Contains("big.ply: header: no end_header line in the first 1048576 bytes"));
  CHECK_FALSE(fs::exists(dir / "out"));
  std::ofstream(dir / "cut.ply") << "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n";
  r = test::run("import cloud " + (dir / "cut.ply").string() + " --out " + (dir / "out").string());
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.output, Contains("cut.ply: header: no end_header line: the header is not complete"));
  CHECK_FALSE(fs::exists(dir / "out"));
}

TEST_CASE("manifest paths: a symbolic link out of the folder is refused, a name with two dots is read") {
  const fs::path dir = test::scratch("robust-cli-paths");
  // a..b.f32: a legal file name, not a ".." component.
  copyDataset(tinyScene(), dir / "dots");
  auto m = readJsonFile(dir / "dots" / "manifest.json");
  fs::rename(dir / "dots" / "scans" / "000000.f32", dir / "dots" / "scans" / "a..b.f32");
  m["scans"][0]["file"] = "scans/a..b.f32";
  writeJsonFile(dir / "dots" / "manifest.json", m);
  auto r = test::run("map --dataset " + (dir / "dots").string() + " --out " + (dir / "dots.ot").string());
  INFO(r.output);
  CHECK(r.exit_code == 0);

  // A scan that is a link to a file outside the data set.
  copyDataset(tinyScene(), dir / "linked");
  fs::rename(dir / "linked" / "scans" / "000001.f32", dir / "outside.f32");
  fs::create_symlink(dir / "outside.f32", dir / "linked" / "scans" / "000001.f32");
  r = test::run("map --dataset " + (dir / "linked").string() + " --out " + (dir / "linked.ot").string());
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.output, Contains("linked/manifest.json: scans[1].file: \"scans/000001.f32\" leads out of the data set folder"));
  CHECK_FALSE(fs::exists(dir / "linked.ot"));
  // A link inside the folder is fine.
  fs::remove(dir / "linked" / "scans" / "000001.f32");
  fs::rename(dir / "outside.f32", dir / "linked" / "real.f32");
  fs::create_symlink("../real.f32", dir / "linked" / "scans" / "000001.f32");
  r = test::run("map --dataset " + (dir / "linked").string() + " --out " + (dir / "linked.ot").string());
  INFO(r.output);
  CHECK(r.exit_code == 0);

  // A ".." component is still refused, by name.
  copyDataset(tinyScene(), dir / "up");
  m = readJsonFile(dir / "up" / "manifest.json");
  m["scans"][0]["file"] = "../dots/scans/a..b.f32";
  writeJsonFile(dir / "up" / "manifest.json", m);
  r = test::run("map --dataset " + (dir / "up").string() + " --out " + (dir / "up.ot").string());
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.output, Contains("scans[0].file: \"../dots/scans/a..b.f32\" must be a relative path inside"));
}

TEST_CASE("a manifest whose truth is not an object is refused by name") {
  const fs::path dir = test::scratch("robust-cli-truth-type");
  copyDataset(tinyScene(), dir / "ds");
  auto m = readJsonFile(dir / "ds" / "manifest.json");
  m["truth"] = 5;
  writeJsonFile(dir / "ds" / "manifest.json", m);
  const auto r = test::run("map --dataset " + (dir / "ds").string() + " --out " + (dir / "m.ot").string());
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.output, Contains("ds/manifest.json: truth: must be an object"));
  CHECK_FALSE(fs::exists(dir / "m.ot"));
}

// TUM RGB-D (cvg.cit.tum.de/data/datasets/rgbd-dataset/file_formats): "timestamp tx ty tz qx qy qz qw".
// A quarter turn about z (qz = qw = sqrt(1/2)) at (1, 2, 3): sensor point (1, 0, 0) -> world (1, 3, 3),
// (0, 2, 0) -> (-1, 2, 3). Worked by hand: R = [0 -1 0; 1 0 0; 0 0 1].
TEST_CASE("pose format tum (--pose-format tum) reads TUM trajectories, timestamp first") {
  const fs::path dir = test::scratch("robust-cli-tum");
  std::ofstream(dir / "c0.xyz") << "1 0 0\n0 2 0\n";
  std::ofstream(dir / "c1.xyz") << "1 0 0\n";
  std::ofstream(dir / "poses.txt") << "# timestamp tx ty tz qx qy qz qw\n"
                                      "1305031102.175304 1 2 3 0 0 0.7071067811865476 0.7071067811865476\n"
                                      "1305031102.211214 -1 0 0.5 0 0 0 1\n";
  auto r = test::run("import cloud " + (dir / "c0.xyz").string() + " " + (dir / "c1.xyz").string() + " --poses " +
                     (dir / "poses.txt").string() + " --pose-format tum --out " + (dir / "ds").string());
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const Dataset d = readDataset(dir / "ds");
  REQUIRE(d.scans.size() == 2);
  CHECK(d.scans[0].origin.x() == Approx(1));
  CHECK(d.scans[0].origin.y() == Approx(2));
  CHECK(d.scans[0].origin.z() == Approx(3));
  CHECK(d.scans[0].points[0].x() == Approx(1).margin(1e-6));
  CHECK(d.scans[0].points[0].y() == Approx(3));
  CHECK(d.scans[0].points[0].z() == Approx(3));
  CHECK(d.scans[0].points[1].x() == Approx(-1));
  CHECK(d.scans[0].points[1].y() == Approx(2).margin(1e-6));
  CHECK(d.scans[1].points[0].x() == Approx(0).margin(1e-6));  // identity rotation, t = (-1, 0, 0.5)
  CHECK(d.scans[1].points[0].z() == Approx(0.5));
  CHECK(d.source.at("pose_format") == "tum");
  // A TUM line read as today's quaternion format says what to do.
  r = test::run("import cloud " + (dir / "c0.xyz").string() + " " + (dir / "c1.xyz").string() + " --poses " +
                (dir / "poses.txt").string() + " --out " + (dir / "ds2").string());
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.output, Contains("poses.txt: line 2: has 8 values, expected 7"));
  CHECK_THAT(r.output, Contains("--pose-format tum"));
  CHECK_FALSE(fs::exists(dir / "ds2"));
}

// KITTI odometry (devkit readme.txt of the odometry benchmark): a line holds the first three rows of the 4x4
// camera-to-world pose, row-major: r11 r12 r13 tx r21 r22 r23 ty r31 r32 r33 tz. A quarter turn about x,
// R = [1 0 0; 0 0 -1; 0 1 0], t = (4, 5, 6): sensor (0, 1, 0) -> (4, 5, 7), (1, 0, 0) -> (5, 5, 6).
TEST_CASE("pose format kitti (--pose-format kitti) reads KITTI's 12 numbers a line") {
  const fs::path dir = test::scratch("robust-cli-kitti");
  std::ofstream(dir / "c0.xyz") << "0 1 0\n1 0 0\n";
  std::ofstream(dir / "poses.txt") << "1 0 0 4 0 0 -1 5 0 1 0 6\n";
  auto r = test::run("import cloud " + (dir / "c0.xyz").string() + " --poses " + (dir / "poses.txt").string() +
                     " --pose-format kitti --out " + (dir / "ds").string());
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const Dataset d = readDataset(dir / "ds");
  REQUIRE(d.scans.size() == 1);
  CHECK(d.scans[0].origin.x() == Approx(4));
  CHECK(d.scans[0].origin.z() == Approx(6));
  CHECK(d.scans[0].points[0].x() == Approx(4));
  CHECK(d.scans[0].points[0].y() == Approx(5));
  CHECK(d.scans[0].points[0].z() == Approx(7));
  CHECK(d.scans[0].points[1].x() == Approx(5));
  CHECK(d.scans[0].points[1].y() == Approx(5));
  CHECK(d.scans[0].points[1].z() == Approx(6));
  // 11 numbers, and a 3x3 that is not a rotation: refused by line.
  std::ofstream(dir / "short.txt") << "1 0 0 4 0 0 -1 5 0 1 0\n";
  r = test::run("import cloud " + (dir / "c0.xyz").string() + " --poses " + (dir / "short.txt").string() +
                " --pose-format kitti --out " + (dir / "bad").string());
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.output, Contains("short.txt: line 1: has 11 values, expected 12"));
  std::ofstream(dir / "shear.txt") << "1 0.5 0 4 0 1 0 5 0 0 1 6\n";
  r = test::run("import cloud " + (dir / "c0.xyz").string() + " --poses " + (dir / "shear.txt").string() +
                " --pose-format kitti --out " + (dir / "bad").string());
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.output, Contains("shear.txt: line 1: pose 1 (from line 1): upper-left 3x3 is not a rotation"));
  CHECK_FALSE(fs::exists(dir / "bad"));
}

TEST_CASE("import truth keeps the name of --dataset, as its help says") {
  const fs::path dir = test::scratch("robust-cli-truth-name");
  copyDataset(tinyScene(), dir / "raw");
  std::ofstream(dir / "boxes.json") << R"({"boxes": [{"min": [-1, -1, 0], "max": [1, 1, 1]}]})";
  const auto help = test::run("import truth --help");
  CHECK_THAT(help.output, Contains("default: the name of --dataset"));
  const auto r = test::run("import truth " + (dir / "boxes.json").string() + " --dataset " + (dir / "raw").string() +
                           " --out " + (dir / "ds").string());
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK(readDataset(dir / "ds").name == readDataset(dir / "raw").name);
  CHECK_THAT(r.output, Contains("data set \"" + readDataset(dir / "raw").name + "\""));
}

TEST_CASE("import --name refuses control characters, as a grid's name does, and shows them escaped") {
  // Old binary: the name was kept, and `compare` printed its line break and escape sequence as they are: a cleared
  // screen and a forged line "knn 0.99".
  const fs::path dir = test::scratch("robust-cli-name-controls");
  std::ofstream(dir / "a.xyz") << "1 0 0\n";
  // printf's octal escapes (the tests' shell is sh): a line break and ESC [2J, a tab, DEL, the C1 control CSI
  // (U+009B) and the bidirectional override U+202E, each as UTF-8.
  const std::vector<std::pair<std::string, std::string>> names = {
      {"a\\n\\033[2Jknn 0.99", "'a\\n\\x1b[2Jknn 0.99'"}, {"tab\\there", "'tab\\there'"}, {"del\\177", "'del\\x7f'"},
      {"c1\\302\\23331m", "'c1\\u009b31m'"}, {"bidi\\342\\200\\256fdp", "'bidi\\u202efdp'"}};
  for (const auto& [octal, shown] : names)
    requireUsageError("import cloud " + (dir / "a.xyz").string() + " --name \"$(printf '" + octal + "')\" --out " +
                          (dir / "ds").string(),
                      "--name must be UTF-8 text without control characters (line breaks, tabs, escape sequences), "
                      "got " + shown, dir);
  // A name of letters beyond ASCII is a name like another.
  const auto r =
      test::run("import cloud " + (dir / "a.xyz").string() + " --name 'Łódź 名字' --out " + (dir / "ds").string());
  INFO(r.output);
  CHECK(r.exit_code == 0);
  CHECK(readDataset(dir / "ds").name == "Łódź 名字");
}

// RFC 3629 worked by hand: what a terminal would act on, or could not show, is escaped; any other UTF-8 stays.
TEST_CASE("names shown on a terminal keep UTF-8 and escape control characters and bytes that are not UTF-8") {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"Łódź 名字 \xf0\x9f\x98\x80 a\\b", "Łódź 名字 \xf0\x9f\x98\x80 a\\b"},  // kept, a backslash too
      {"a\nb\r\t\x1b[2J\x7f", "a\\nb\\r\\t\\x1b[2J\\x7f"},          // C0 and DEL
      {"\xc2\x85\xc2\x9b\xe2\x80\xae\xe2\x81\xa6", "\\u0085\\u009b\\u202e\\u2066"},  // C1, bidirectional
      {"\xc2\xa0|\xe2\x80\xaf", "\xc2\xa0|\xe2\x80\xaf"},  // U+00A0 after the C1 controls, U+202F after U+202E
      {"\xc0\xaf", "\\xc0\\xaf"},                            // an overlong '/'
      {"\xed\xa0\x80", "\\xed\\xa0\\x80"},                  // a surrogate
      {"\xf4\x90\x80\x80", "\\xf4\\x90\\x80\\x80"},          // above U+10FFFF
      {"\xe5\x90", "\\xe5\\x90"},                            // cut short
      {"\xff", "\\xff"}};
  for (const auto& [text, shown] : cases) {
    INFO(shown);
    CHECK(escapedControlCharacters(text) == shown);
    CHECK(hasControlCharacters(text) == (shown != text));
  }
}

TEST_CASE("progress into a log is whole lines, and mapdiff prints its JSON alone") {
  const fs::path dir = test::scratch("robust-cli-logs");
  std::ofstream(dir / "a.xyz") << "1 0 0\n";
  std::ofstream(dir / "b.xyz") << "0 1 0\n";
  auto r = test::run("import cloud " + (dir / "a.xyz").string() + " " + (dir / "b.xyz").string() + " --out " +
                     (dir / "ds").string());  // stderr is a pipe here, not a terminal
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK(r.output.find('\r') == std::string::npos);
  CHECK_THAT(r.output, Contains("point cloud 2/2\n"));

  for (const char* method : {"octomap", "knn"})
    REQUIRE(test::run("map --dataset " + tinyScene().string() + " --method " + method + " --out " +
                      (dir / (std::string(method) + ".ot")).string())
                .exit_code == 0);
  r = test::run("mapdiff " + (dir / "octomap.ot").string() + " " + (dir / "knn.ot").string());
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK_THAT(r.output, !Contains("Reading octree type"));
  CHECK_NOTHROW(nlohmann::json::parse(r.output));  // stdout and stderr together: nothing but the JSON
  // A file that is not a map: occsweep's own message naming the file (its reader checks the bytes before
  // liboctomap sees them), not liboctomap's raw lines.
  std::ofstream(dir / "junk.ot") << "not an octree\n";
  r = test::run("mapdiff " + (dir / "junk.ot").string() + " " + (dir / "knn.ot").string());
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.output, Contains("junk.ot: magic: not an OctoMap .ot file"));
  CHECK_THAT(r.output, !Contains("\nERROR: "));
}

// docs/grids.md: JSON keeps only the last of two equal keys, so a grid that gives one twice lost the first
// silently; it is refused, naming the file and the key.
TEST_CASE("a grid file that gives a key twice is refused, naming the file and the key") {
  const fs::path dir = test::scratch("robust-cli-duplicate-key");
  std::ofstream(dir / "dup.json") << R"({"name": "dup", "method": "octomap", "parameters": {
    "p_max": {"value": 0.97}, "p_min": {"value": 0.12}, "p_h": {"min": 0.6, "max": 0.9, "step": 0.3},
    "p_h": {"value": 0.7}, "p_m": {"min": 0.2, "max": 0.4, "step": 0.2}, "p_t": {"step": 0.3}}})";
  std::ofstream(dir / "dup-top.json") << R"({"name": "a", "name": "b", "method": "octomap", "parameters": {
    "p_max": {"value": 0.97}, "p_min": {"value": 0.12}, "p_h": {"value": 0.7}, "p_m": {"value": 0.2},
    "p_t": {"step": 0.3}}})";
  for (const auto& [file, key] : {std::pair{"dup.json", "parameters.p_h"}, {"dup-top.json", "name"}}) {
    const auto r = test::runCli("grid count " + (dir / file).string());
    INFO(r.output);
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.output, Contains((dir / file).string() + ": " + key + ": key given twice"));
  }
}

// docs/robustness.md, "Messages, formats and the cluster": no message is a library's raw text ("stoull",
// "filesystem error: ..."); each names the flag or the path and the rule.
TEST_CASE("cluster plan names the flag or the folder where a library's raw error text was printed") {
  const fs::path dir = test::scratch("robust-cli-raw-errors");
  auto r = test::runCli("cluster plan --out " + (dir / "p").string() + " --grid octomap-opt:99999999999999999999999");
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.output, Contains("--grid 'octomap-opt:99999999999999999999999': shards must be a whole number from 1 "
                                "to 18446744073709551615"));
  CHECK_FALSE(fs::exists(dir / "p"));
  std::ofstream(dir / "a-file") << "mine\n";
  r = test::runCli("cluster plan --out " + (dir / "a-file" / "p").string() + " --experiment sweep --dataset " +
                   (dir / "ds").string() + " --grid octomap-opt:1");
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.output, Contains((dir / "a-file" / "p").string() + ": cannot create the plan folder: Not a directory"));
  CHECK(r.output.find("filesystem error") == std::string::npos);
  CHECK(test::bytesOf(dir / "a-file") == "mine\n");
}
