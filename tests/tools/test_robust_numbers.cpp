// "No silent wrong number" (docs/robustness.md, "Numbers that must not be wrong"): coordinates outside
// OctoMap's key range, float overflow at import, results files that claim more than they hold, comparisons of
// results that do not compare, numbers without a meaning, and help text that claims what is not true.
// Each case runs the real command. OCCSWEEP_TEST_CLI=/path/to/occsweep runs them against another binary (the
// evidence that each fails on the code before the fix).
#include <catch2/catch.hpp>

#include <cstdlib>
#include <fstream>

#include <nlohmann/json.hpp>

#include "occsweep/eval/dataset.hpp"
#include "occsweep/core/splitmix64.hpp"
#include "test_helpers.hpp"

using namespace occsweep;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

const fs::path kSource = occsweep::test::sourceTree();

test::CommandResult run(const std::string& args) { return test::runCli(args); }

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }
// `text` with every run of spaces and line breaks as one space: compare wraps its notes at 100 columns.
std::string flat(const std::string& text) {
  std::string out;
  for (char ch : text) {
    const bool blank = ch == ' ' || ch == '\n';
    if (!blank || out.empty() || out.back() != ' ') out += blank ? ' ' : ch;
  }
  return out;
}

// `text` without any space or line break: a note naming a path that compare cut at its lines' ends, read whole.
std::string squeezed(const std::string& text) {
  std::string out;
  for (char ch : text)
    if (ch != ' ' && ch != '\n') out += ch;
  return out;
}

void writeFile(const fs::path& file, const std::string& bytes) { std::ofstream(file, std::ios::binary) << bytes; }

json readJson(const fs::path& file) { return json::parse(std::ifstream(file)); }
void writeJson(const fs::path& file, const json& j) { std::ofstream(file) << j.dump(1); }

bool tmpLeft(const fs::path& dir) {
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (has(e.path().filename().string(), ".tmp-")) return true;
  return false;
}

// A wall 2 m in front of the sensor (21 x 21 points), shifted by `x0` on x.
std::string wallXyz(double x0) {
  std::string s;
  for (int i = 0; i <= 20; ++i)
    for (int j = 0; j <= 20; ++j)
      s += std::to_string(x0 + 2.0) + " " + std::to_string(-0.5 + 0.05 * i) + " " + std::to_string(0.05 * j) + "\n";
  return s;
}

// The wall as a data set with its truth box and a small region (a few thousand voxels): sweeps take a second.
fs::path wallDataset(const fs::path& dir, const std::string& name, bool with_truth = true) {
  writeFile(dir / "wall.xyz", wallXyz(0));
  const fs::path raw = dir / (name + "-raw"), out = dir / name;
  REQUIRE(run("import cloud " + (dir / "wall.xyz").string() + " --origin 0 0 0.5 --out " + raw.string()).exit_code == 0);
  if (!with_truth) return raw;
  writeFile(dir / "wall_truth.json", R"({"boxes": [{"min": [1.95, -0.5, 0], "max": [2.05, 0.5, 1]}]})");
  REQUIRE(run("import truth " + (dir / "wall_truth.json").string() + " --dataset " + raw.string() +
              " --region -0.2 -0.7 -0.2 2.4 0.7 1.2 --out " + out.string())
              .exit_code == 0);
  return out;
}

// A k-NN grid small enough for a test: 2 maps x 9 thresholds.
fs::path tinyKnnGrid(const fs::path& dir) {
  writeFile(dir / "knn-tiny.json", R"({"name": "knn-tiny", "method": "knn", "parameters": {
    "p_max": {"value": 0.98}, "p_min": {"value": 0.02}, "p_m": {"value": 0.26}, "p_m_out": {"value": 0.38},
    "p_u": {"value": 0.86}, "p_l": {"value": 0.14}, "p_t": {"step": 0.12}, "k": [1, 3]}})");
  return dir / "knn-tiny.json";
}

void requireRefused(const test::CommandResult& r, const std::vector<std::string>& parts) {
  INFO(r.output);
  CHECK(r.exit_code == 2);
  for (const auto& p : parts) CHECK(has(r.output, p));
  CHECK(!has(r.output, "Segmentation"));
}

}  // namespace

TEST_CASE("coordinates outside OctoMap's key range are refused by map and sweep, naming the field and the range") {
  const fs::path dir = test::scratch("robust_numbers_keys");
  const fs::path wall = wallDataset(dir, "wall");

  SECTION("a region of +-1e30 (old: evaluated as one voxel)") {
    fs::copy(wall, dir / "far_region", fs::copy_options::recursive);
    json m = readJson(dir / "far_region/manifest.json");
    m["region"] = {{"min", {-1e30, -1e30, -1e30}}, {"max", {1e30, 1e30, 1e30}}};
    writeJson(dir / "far_region/manifest.json", m);
    for (const std::string method : {"octomap", "knn"}) {
      requireRefused(run("map --dataset " + (dir / "far_region").string() + " --method " + method + " --out " +
                         (dir / "r.ot").string()),
                     {"far_region/manifest.json", "region", "key range [-3276.8, 3276.8) m at resolution 0.1 m"});
      CHECK(!fs::exists(dir / "r.ot"));
    }
    requireRefused(run("sweep --dataset " + (dir / "far_region").string() + " --grid octomap-opt --quiet --out " +
                       (dir / "r.json").string()),
                   {"far_region/manifest.json", "region", "key range"});
    CHECK(!fs::exists(dir / "r.json"));
    CHECK(!tmpLeft(dir));
  }

  SECTION("a truth box of +-1e30 (old: added no truth voxel)") {
    fs::copy(wall, dir / "far_truth", fs::copy_options::recursive);
    json m = readJson(dir / "far_truth/manifest.json");
    m["truth"]["boxes"][0] = {{"min", {-1e30, -1e30, -1e30}}, {"max", {1e30, 1e30, 1e30}}};
    writeJson(dir / "far_truth/manifest.json", m);
    requireRefused(run("map --dataset " + (dir / "far_truth").string() + " --out " + (dir / "t.ot").string()),
                   {"far_truth/manifest.json", "truth.boxes[0]", "key range"});
    CHECK(!fs::exists(dir / "t.ot"));
  }

  SECTION("a UTM-like cloud at x = 500000 (old: empty maps, all TN): refused with the --shift to pass; "
          "imported with it, it maps, and the shift is recorded") {
    writeFile(dir / "utm.xyz", wallXyz(500000));
    auto r = run("import cloud " + (dir / "utm.xyz").string() + " --origin 500000 0 0.5 --out " + (dir / "utm").string());
    REQUIRE(r.exit_code == 0);
    CHECK(has(r.output, "--shift -500001 0 0"));  // the warning at import already says what to pass
    for (const std::string method : {"octomap", "knn"}) {
      requireRefused(run("map --dataset " + (dir / "utm").string() + " --method " + method + " --out " +
                         (dir / "u.ot").string()),
                     {"utm/manifest.json", "scans[0]", "key range", "--shift -500001 0 0"});
      CHECK(!fs::exists(dir / "u.ot"));
    }
    requireRefused(run("sweep --dataset " + (dir / "utm").string() + " --grid octomap-opt --quiet --out " +
                       (dir / "u.json").string()),
                   {"utm/manifest.json", "--shift"});
    // At a resolution whose range holds 500000 m (16 m: +-524288 m) the same data set is accepted.
    CHECK(run("map --dataset " + (dir / "utm").string() + " --method octomap --resolution 16 --s-c 40 --out " +
              (dir / "coarse.ot").string()).exit_code == 0);

    r = run("import cloud " + (dir / "utm.xyz").string() + " --origin 500000 0 0.5 --shift -500001 0 0 --out " +
            (dir / "utm_shifted").string());
    REQUIRE(r.exit_code == 0);
    CHECK(!has(r.output, "warning"));
    CHECK(readJson(dir / "utm_shifted/manifest.json")["source"]["shift"] == json({-500001.0, 0.0, 0.0}));
    const Dataset shifted = readDataset(dir / "utm_shifted");
    CHECK(shifted.scans[0].origin.x() == Approx(-1.0));
    CHECK(shifted.scans[0].points[0].x() == Approx(1.0));
    // Truth and region given in the recording's frame land on the shifted scans.
    writeFile(dir / "utm_truth.json", R"({"boxes": [{"min": [500001.95, -0.5, 0], "max": [500002.05, 0.5, 1]}]})");
    REQUIRE(run("import truth " + (dir / "utm_truth.json").string() + " --dataset " + (dir / "utm_shifted").string() +
                " --region 499999.8 -0.7 -0.2 500002.4 0.7 1.2 --out " + (dir / "utm_truth").string()).exit_code == 0);
    const Dataset with_truth = readDataset(dir / "utm_truth");
    CHECK(with_truth.truth.boxes[0].min[0] == Approx(0.95));
    CHECK(with_truth.region.min[0] == Approx(-1.2));
    CHECK(with_truth.region.max[0] == Approx(1.4));
    r = run("map --dataset " + (dir / "utm_truth").string() + " --method octomap --out " + (dir / "s.ot").string());
    INFO(r.output);
    CHECK(r.exit_code == 0);
    CHECK(!has(r.output, "TP 0 "));
  }
}

TEST_CASE("import refuses values that overflow float32, naming the file or flag, and writes nothing") {
  const fs::path dir = test::scratch("robust_numbers_overflow");
  const fs::path out = dir / "out";
  auto refused = [&](const std::string& args, const std::vector<std::string>& parts) {
    fs::remove_all(out);
    requireRefused(run(args + " --out " + out.string()), parts);
    CHECK(!fs::exists(out));
    CHECK(!tmpLeft(dir));
  };
  const std::string ply_head = "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
                               "property float z\nend_header\n";
  SECTION("x y z text 1e39") {
    writeFile(dir / "big.xyz", "1 2 3\n1e39 0 0\n");
    refused("import cloud " + (dir / "big.xyz").string(), {"big.xyz", "point 1", "float32"});
  }
  SECTION("ASCII PLY 1e39") {
    writeFile(dir / "big.ply", ply_head + "1 2 3\n0 -1e39 0\n");
    refused("import cloud " + (dir / "big.ply").string(), {"big.ply", "float32"});
  }
  SECTION("binary double PLY 1e300") {
    std::string b = "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty double x\nproperty double y\n"
                    "property double z\nend_header\n";
    const double v[3] = {1, 1e300, 2};
    b.append(reinterpret_cast<const char*>(v), sizeof v);
    writeFile(dir / "double.ply", b);
    refused("import cloud " + (dir / "double.ply").string(), {"double.ply", "float32"});
  }
  SECTION("binary double PCD 1e300") {
    std::string b = "VERSION 0.7\nFIELDS x y z\nSIZE 8 8 8\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 1\nHEIGHT 1\n"
                    "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 1\nDATA binary\n";
    const double v[3] = {1e300, 0, 2};
    b.append(reinterpret_cast<const char*>(v), sizeof v);
    writeFile(dir / "double.pcd", b);
    refused("import cloud " + (dir / "double.pcd").string(), {"double.pcd", "float32"});
  }
  SECTION("a pose translation of 1e39") {
    writeFile(dir / "ok.xyz", "1 2 3\n");
    writeFile(dir / "far_pose.txt", "1e39 0 0 0 0 0 1\n");
    refused("import cloud " + (dir / "ok.xyz").string() + " --poses " + (dir / "far_pose.txt").string(),
            {"ok.xyz", "far_pose.txt", "float32"});
  }
  SECTION("--depth-scale 1e-300 and --fx 1e-300") {
    writeFile(dir / "d.pgm", "P2 2 1 65535\n1000 2000\n");
    writeFile(dir / "pose.txt", "0 0 0 0 0 0 1\n");
    const std::string base = "import depth " + (dir / "d.pgm").string() + " --poses " + (dir / "pose.txt").string();
    refused(base + " --depth-scale 1e-300 --fx 500 --fy 500 --cx 1 --cy 1", {"d.pgm", "--depth-scale", "float32"});
    refused(base + " --fx 1e-300 --fy 500 --cx 0 --cy 1", {"d.pgm", "--fx", "float32"});
  }
  SECTION("a truth PLY with 1e300") {
    writeFile(dir / "ok.xyz", "1 2 3\n");
    REQUIRE(run("import cloud " + (dir / "ok.xyz").string() + " --out " + (dir / "okset").string()).exit_code == 0);
    std::string b = "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty double x\nproperty double y\n"
                    "property double z\nend_header\n";
    const double v[3] = {0, 0, -1e300};
    b.append(reinterpret_cast<const char*>(v), sizeof v);
    writeFile(dir / "truth.ply", b);
    refused("import truth " + (dir / "truth.ply").string() + " --dataset " + (dir / "okset").string(),
            {"truth.ply", "float32"});
  }
  SECTION("a --shift that overflows") {
    writeFile(dir / "big_ok.xyz", "3e38 0 0\n");
    refused("import cloud " + (dir / "big_ok.xyz").string() + " --shift 1e38 0 0", {"--shift", "float32"});
  }
}

TEST_CASE("property: an import that succeeds yields a data set that every reader accepts") {
  const fs::path dir = test::scratch("robust_numbers_property");
  SplitMix64 rng(13);
  const double edges[] = {1e39, -1e39, 3.5e38, 1e300, -1e300, 3.4e38, -3.4e38, 1e-45, 5e5, 0.0, 1e-300};
  int succeeded = 0, refused = 0;
  for (int trial = 0; trial < 24; ++trial) {
    std::string xyz;
    const int points = 1 + int(rng.below(4));
    for (int p = 0; p < points; ++p) {
      for (int a = 0; a < 3; ++a) {
        const double v = rng.uniform() < 0.3 ? edges[rng.below(std::size(edges))] : (rng.uniform() - 0.5) * 20;
        char buf[40];
        std::snprintf(buf, sizeof buf, "%.17g ", v);
        xyz += buf;
      }
      xyz += "\n";
    }
    const fs::path in = dir / ("p" + std::to_string(trial) + ".xyz"), out = dir / ("d" + std::to_string(trial));
    writeFile(in, xyz);
    std::string pose_args;
    if (rng.uniform() < 0.3) {  // sometimes a pose that moves the points far
      writeFile(dir / "pose.txt", std::to_string(rng.uniform() < 0.5 ? 3.3e38 : 10.0) + " 0 0 0 0 0 1\n");
      pose_args = " --poses " + (dir / "pose.txt").string();
    }
    const auto r = run("import cloud " + in.string() + pose_args + " --out " + out.string());
    INFO("trial " << trial << ": " << xyz << r.output);
    if (r.exit_code == 0) {
      ++succeeded;
      CHECK_NOTHROW((void)readDataset(out));
      // map either builds it or refuses by the key-range rule; never a reader error on what import wrote
      const auto m = run("map --dataset " + out.string() + " --method octomap --out " +
                         (dir / ("m" + std::to_string(trial) + ".ot")).string());
      INFO(m.output);
      CHECK((m.exit_code == 0 || (m.exit_code == 2 && has(m.output, "key range"))));
    } else {
      ++refused;
      CHECK(r.exit_code == 2);
      CHECK(has(r.output, in.filename().string()));
      CHECK(!fs::exists(out));
    }
  }
  CHECK(succeeded > 0);
  CHECK(refused > 0);
}

namespace {

// A complete results file of a real sweep, and its checked twin through `results check`.
struct ResultsFixture {
  fs::path dir, wall, octomap, knn;
  ResultsFixture() {
    dir = test::processScratch("robust_numbers_results");  // two cases run it at once
    wall = wallDataset(dir, "wall");
    octomap = dir / "octomap.json";
    knn = dir / "knn.json";
    REQUIRE(run("sweep --dataset " + wall.string() + " --grid octomap-opt --quiet --out " + octomap.string()).exit_code == 0);
    REQUIRE(run("sweep --dataset " + wall.string() + " --grid " + tinyKnnGrid(dir).string() + " --quiet --out " +
                knn.string()).exit_code == 0);
  }
};

// Rewrites the FPR from the counts, as a careful hand edit of TN would (TPR, FDR, precision and AUC do not
// depend on TN).
void recomputeFpr(json& map) {
  for (auto& t : map["thresholds"]) {
    const double fp = t["fp"].get<double>(), tn = t["tn"].get<double>();
    t["fpr"] = fp + tn > 0 ? json(fp / (fp + tn)) : json(nullptr);
  }
}

}  // namespace

TEST_CASE("results check and compare refuse results files that claim more than they hold") {
  ResultsFixture fx;
  REQUIRE(run("results check " + fx.octomap.string()).exit_code == 0);
  REQUIRE(run("results check " + fx.knn.string()).exit_code == 0);
  const json octomap = readJson(fx.octomap), knn = readJson(fx.knn);
  auto refusedEdit = [&](const std::string& name, json edited, const std::vector<std::string>& parts) {
    INFO(name);
    const fs::path file = fx.dir / (name + ".json");
    writeJson(file, edited);
    requireRefused(run("results check " + file.string()), std::vector<std::string>{file.filename().string()});
    const auto r = run("results check " + file.string());
    for (const auto& p : parts) CHECK(has(r.output, p));
    const bool is_knn = edited["grid"]["method"] == "knn";
    requireRefused(run("compare " + file.string() + " " + (is_knn ? fx.octomap : fx.knn).string()),
                   {file.filename().string()});
  };
  json e = octomap;
  e["maps"].push_back(e["maps"][0]);
  refusedEdit("duplicated_map", e, {"duplicated map"});
  e = octomap;
  e["maps"][1] = e["maps"][0];  // map 0 twice, map 1 gone: the count of ids still matches
  refusedEdit("map_twice_one_missing", e, {"map"});
  e = octomap;
  e["maps"][0]["thresholds"].push_back(e["maps"][0]["thresholds"].back());
  refusedEdit("duplicated_threshold", e, {"duplicated threshold"});
  e = octomap;
  e["maps"].erase(e["maps"].begin() + 3);
  refusedEdit("missing_map", e, {"maps"});
  e = octomap;
  e["maps"] = json::array();
  refusedEdit("no_maps", e, {"maps"});
  e = knn;
  e["maps"][0]["params"]["k"] = (std::uint64_t(1) << 32) + 1;
  refusedEdit("k_wraps", e, {"params.k"});
  e = octomap;
  e["map"]["resolution"] = -0.1;
  refusedEdit("negative_resolution", e, {"map.resolution"});
  // Eq. 12 between the parameters of one map, checked from the method's declaration even where the grid file is not
  // found (previous code: each parameter within its bounds passed, p_u < p_l too).
  e = knn;
  e["grid"]["name"] = "a-grid-nobody-has";
  e["maps"][0]["params"]["p_u"] = 0.5;
  e["maps"][0]["params"]["p_l"] = 0.99;
  refusedEdit("p_u_below_p_l", e, {"maps[0].params", "parameters break Eq. 12: p_u >= p_l does not hold"});
  e = octomap;
  for (auto& m : e["maps"]) {
    for (auto& t : m["thresholds"]) t["tn"] = t["tn"].get<std::uint64_t>() + (std::uint64_t(1) << 63);
    recomputeFpr(m);
  }
  refusedEdit("tn_plus_2_63", e, {"2^48"});
  e = octomap;
  e["selection"]["group"] = {{"index", 0}, {"count", ~std::uint64_t(0)}, {"seed", 0}};
  refusedEdit("group_count_max", e, {"selection.group.count"});

  // A key given twice in one object: JSON keeps the last, another reader the first (old binary: passed, and compare
  // printed the last value while the file showed a first of 0.99).
  {
    const fs::path file = fx.dir / "duplicate_key.json";
    std::string text = test::bytesOf(fx.octomap);
    const std::string anchored = "\"anchored\": ";
    const std::size_t at = text.find(anchored);
    REQUIRE(at != std::string::npos);
    text.insert(at, anchored + "0.99, ");
    std::ofstream(file, std::ios::trunc) << text;
    requireRefused(run("results check " + file.string()), {"duplicate_key.json", "auc.anchored", "key given twice"});
    requireRefused(run("compare " + file.string() + " " + fx.knn.string()), {"duplicate_key.json", "key given twice"});
  }

  // Counts that agree with each other but not with the data set: only the data set can tell.
  auto r = run("results check " + fx.octomap.string() + " --dataset " + fx.wall.string());
  INFO(r.output);
  CHECK(r.exit_code == 0);
  CHECK(has(r.output, "counts match the region and truth"));
  e = octomap;
  for (auto& m : e["maps"]) {
    for (auto& t : m["thresholds"]) t["tn"] = t["tn"].get<std::uint64_t>() + 1000;
    recomputeFpr(m);
  }
  writeJson(fx.dir / "tn_plus_1000.json", e);
  CHECK(run("results check " + (fx.dir / "tn_plus_1000.json").string()).exit_code == 0);  // consistent in itself
  requireRefused(run("results check " + (fx.dir / "tn_plus_1000.json").string() + " --dataset " + fx.wall.string()),
                 {"tn_plus_1000.json", "TP+FP+FN+TN", "voxels"});
  requireRefused(run("results check " + fx.octomap.string() + " --dataset " + (fx.dir / "wall-raw").string()),
                 {"octomap.json", "dataset.content_hash", "another data set"});
}

TEST_CASE("compare refuses results that do not compare, names the file behind every number, prints no NaN") {
  ResultsFixture fx;
  const fs::path grid = tinyKnnGrid(fx.dir);
  auto sweep = [&](const std::string& grid_arg, const std::string& extra, const fs::path& out) {
    REQUIRE(run("sweep --dataset " + fx.wall.string() + " --grid " + grid_arg + " --quiet " + extra + " --out " +
                out.string()).exit_code == 0);
    return out;
  };
  SECTION("files of one setting: every row names its files, in the table and in --json") {
    const auto r = run("compare " + fx.octomap.string() + " " + fx.knn.string() + " --json " +
                       (fx.dir / "cmp.json").string());
    INFO(r.output);
    REQUIRE(r.exit_code == 0);
    CHECK(has(test::joinedLines(r.output), fx.octomap.string()));  // whole, however long the test's folder
    CHECK(has(test::joinedLines(r.output), fx.knn.string()));
    const json j = readJson(fx.dir / "cmp.json");
    CHECK(j["rows"][0]["methods"]["octomap"]["file"] == fx.octomap.string());
    CHECK(j["rows"][0]["methods"]["knn"]["file"] == fx.knn.string());
  }
  SECTION("a shard against a whole grid (old: -16.88 % from a third of the grid)") {
    const fs::path shard = sweep(grid.string(), "--shard 0/2", fx.dir / "shard.json");
    auto r = run("compare " + shard.string() + " " + fx.octomap.string());
    requireRefused(r, {"shard.json", "shard 0/2", "--allow-mixed"});
    r = run("compare --allow-mixed " + shard.string() + " " + fx.octomap.string());
    INFO(r.output);
    CHECK(r.exit_code == 0);
    CHECK(has(r.output, "warning"));
    CHECK(has(r.output, "shard.json"));
  }
  SECTION("an Eq. 16 group against a whole grid (old: compared as if the group were the grid)") {
    const fs::path group = sweep(grid.string(), "--group 1/3 --seed 7", fx.dir / "group.json");
    requireRefused(run("compare " + group.string() + " " + fx.octomap.string()),
                   {"group.json", "group 1/3", "Eq. 16", "--allow-mixed"});
    const auto r = run("compare --allow-mixed " + group.string() + " " + fx.octomap.string());
    INFO(r.output);
    CHECK(r.exit_code == 0);
    CHECK(has(r.output, "warning"));
    // Every table a paper takes says so too (old binary: the CSV, Markdown and LaTeX tables carried the numbers
    // unmarked, the warning on stderr only).
    const std::string tables = " --csv " + (fx.dir / "mixed.csv").string() + " --markdown " +
                               (fx.dir / "mixed.md").string() + " --latex " + (fx.dir / "mixed.tex").string();
    for (const char* t : {"mixed.csv", "mixed.md", "mixed.tex"}) fs::remove(fx.dir / t);
    REQUIRE(run("compare --allow-mixed " + group.string() + " " + fx.octomap.string() + tables).exit_code == 0);
    std::ifstream csv(fx.dir / "mixed.csv");
    std::string header, line;
    std::getline(csv, header);
    CHECK(header.starts_with("dataset,point_cloud_set,dataset_hash,mixed_settings,"));
    int rows = 0;
    while (std::getline(csv, line)) {
      ++rows;
      CHECK(line.find(",yes,") != std::string::npos);
    }
    CHECK(rows > 0);
    const std::string note = "Mixed settings (compare --allow-mixed): the files differ in";
    CHECK(has(test::bytesOf(fx.dir / "mixed.md"), note));
    CHECK(has(test::bytesOf(fx.dir / "mixed.tex"), "Mixed settings (compare -{}-allow-mixed): the files differ in"));
    // Without --allow-mixed nothing is marked: the column and the note are absent.
    const std::string clean = " --csv " + (fx.dir / "clean.csv").string() + " --force";
    REQUIRE(run("compare " + fx.octomap.string() + " " + fx.knn.string() + clean).exit_code == 0);
    CHECK_FALSE(has(test::bytesOf(fx.dir / "clean.csv"), "mixed_settings"));
  }
  SECTION("two results of one method for one set, or one file twice (old: the better one taken without a word)") {
    const fs::path again = fx.dir / "again.json";
    fs::copy_file(fx.knn, again, fs::copy_options::overwrite_existing);
    requireRefused(run("compare " + fx.octomap.string() + " " + fx.knn.string() + " " + again.string()),
                   {"again.json", "two results of method knn for one data set", "--allow-mixed"});
    requireRefused(run("compare " + fx.octomap.string() + " " + fx.knn.string() + " " + fx.knn.string()),
                   {"the same file given twice", "--allow-mixed"});
    const auto r = run("compare --allow-mixed " + fx.octomap.string() + " " + fx.knn.string() + " " + again.string());
    INFO(r.output);
    CHECK(r.exit_code == 0);
    CHECK(has(r.output, "warning (--allow-mixed)"));
  }
  SECTION("the verdicts' alpha and smallest effect must be numbers in their range (the old binary took nan)") {
    for (const std::string flag : {"--alpha nan", "--alpha inf", "--alpha 0.5", "--smallest-effect nan",
                                   "--smallest-effect -1"}) {
      const auto r = run("compare " + flag + " " + fx.octomap.string() + " " + fx.knn.string());
      INFO(flag << ": " << r.output);
      CHECK(r.exit_code == 2);
      CHECK(has(r.output, flag.substr(0, flag.find(' '))));
      CHECK(has(r.output, "must be a number in ["));
    }
  }
  SECTION("two outputs naming one file are refused before anything is written (on the old binary the CSV overwrote "
          "the JSON)") {
    const fs::path both = fx.dir / "both.out";
    const auto r = run("compare " + fx.octomap.string() + " " + fx.knn.string() + " --json " + both.string() +
                       " --csv " + (fx.dir / "." / "both.out").string());
    INFO(r.output);
    CHECK(r.exit_code == 2);
    CHECK(has(r.output, "--json and --csv name one file"));
    CHECK_FALSE(fs::exists(both));
    // Through a symbolic link and "..", read as the writer reads it or as the disk resolves it, or with a trailing
    // '/': still one file (old: the CSV replaced the JSON).
    fs::create_directories(fx.dir / "deep" / "dir");
    fs::create_symlink(fx.dir / "deep" / "dir", fx.dir / "link");
    const std::string via_link = (fx.dir / "link" / ".." / "both.out").string();
    for (const auto& [json_out, csv_out] : std::vector<std::pair<std::string, std::string>>{
             {both.string(), via_link}, {(fx.dir / "deep" / "both.out").string(), via_link},
             {both.string(), both.string() + "/"}}) {
      const auto again = run("compare " + fx.octomap.string() + " " + fx.knn.string() + " --json " + json_out +
                             " --csv " + csv_out);
      INFO(json_out << " and " << csv_out << ": " << again.output);
      CHECK(again.exit_code == 2);
      CHECK(has(again.output, "name one file"));
      CHECK_FALSE(fs::exists(both));
      CHECK_FALSE(fs::exists(fx.dir / "deep" / "both.out"));
    }
  }
  SECTION("an output under a file is refused before any output is written (the old binary wrote --json)") {
    writeFile(fx.dir / "afile", "a user's file\n");
    const auto r = run("compare " + fx.octomap.string() + " " + fx.knn.string() + " --json " +
                       (fx.dir / "j.json").string() + " --latex " + (fx.dir / "afile" / "x.tex").string());
    INFO(r.output);
    CHECK(r.exit_code == 2);
    CHECK(has(r.output, "--latex"));
    CHECK(has(r.output, "afile is not a folder"));
    CHECK_FALSE(fs::exists(fx.dir / "j.json"));
    // One output under another, and one through a broken symbolic link (old: the JSON was written, then exit 2).
    fs::create_symlink(fx.dir / "nowhere" / "zz", fx.dir / "dangling");
    for (const auto& [flags, says] : std::vector<std::pair<std::string, std::string>>{
             {" --json " + (fx.dir / "a").string() + " --csv " + (fx.dir / "a" / "b.csv").string(), "lies under"},
             {" --csv " + (fx.dir / "a" / "b.csv").string() + " --json " + (fx.dir / "a").string(), "lies under"},
             {" --json " + (fx.dir / "a").string() + " --csv " + (fx.dir / "dangling" / "x.csv").string(),
              "dangling is not a folder"}}) {
      const auto again = run("compare " + fx.octomap.string() + " " + fx.knn.string() + flags);
      INFO(flags << ": " << again.output);
      CHECK(again.exit_code == 2);
      CHECK(has(again.output, says));
      CHECK_FALSE(fs::exists(fx.dir / "a"));
    }
  }
  SECTION("k-NN at 0.2 m against OctoMap at 0.1 m (old: -24.60 %)") {
    const fs::path coarse = sweep(grid.string(), "--resolution 0.2", fx.dir / "coarse.json");
    requireRefused(run("compare " + coarse.string() + " " + fx.octomap.string()),
                   {"coarse.json", "octomap.json", "resolution"});
  }
  SECTION("two k-NN files with different s_c (old: silently merged)") {
    const fs::path other = sweep(grid.string(), "--s-c 3", fx.dir / "sc3.json");
    requireRefused(run("compare " + other.string() + " " + fx.knn.string() + " " + fx.octomap.string()),
                   {"sc3.json", "knn.json", "s_c"});
  }
  SECTION("a variant and a statistics mode that differ") {
    const fs::path other = sweep(grid.string(), "--stats online", fx.dir / "online.json");
    requireRefused(run("compare " + other.string() + " " + fx.knn.string()), {"online.json", "statistics mode"});
  }
  SECTION("one data set name with another truth: never compared, and the row says why") {
    writeFile(fx.dir / "other_truth.json", R"({"boxes": [{"min": [1.85, -0.5, 0], "max": [2.05, 0.5, 1]}]})");
    REQUIRE(run("import truth " + (fx.dir / "other_truth.json").string() + " --dataset " + fx.wall.string() +
                " --out " + (fx.dir / "wall_other").string()).exit_code == 0);
    REQUIRE(run("sweep --dataset " + (fx.dir / "wall_other").string() + " --grid " + grid.string() +
                " --quiet --out " + (fx.dir / "k_other.json").string()).exit_code == 0);
    const auto r = run("compare " + fx.octomap.string() + " " + (fx.dir / "k_other.json").string());
    INFO(r.output);
    CHECK(r.exit_code == 0);
    CHECK(!has(r.output, "nan"));
    CHECK(has(squeezed(r.output), squeezed("k_other.json is of data set")));
    CHECK(has(flat(r.output), "other contents"));
  }
  SECTION("sweeps without ground truth (old: nan nan nan, exit 0, no reason)") {
    const fs::path raw = fx.dir / "wall-raw";  // the data set before `import truth`
    REQUIRE(run("sweep --dataset " + raw.string() + " --grid octomap-opt --quiet --out " +
                (fx.dir / "o_raw.json").string()).exit_code == 0);
    REQUIRE(run("sweep --dataset " + raw.string() + " --grid " + grid.string() + " --quiet --out " +
                (fx.dir / "k_raw.json").string()).exit_code == 0);
    const auto r = run("compare " + (fx.dir / "o_raw.json").string() + " " + (fx.dir / "k_raw.json").string());
    INFO(r.output);
    CHECK(r.exit_code == 0);
    CHECK(!has(r.output, "nan"));
    CHECK(has(flat(r.output), "no ground truth"));
    CHECK(has(test::joinedLines(r.output), "o_raw.json"));
  }
}

TEST_CASE("map warns when every point is beyond s_c, naming s_c and the nearest point's range") {
  const fs::path dir = test::scratch("robust_numbers_sc");
  const fs::path wall = wallDataset(dir, "wall");
  auto r = run("map --dataset " + wall.string() + " --method knn --s-c 1.5 --out " + (dir / "far.ot").string());
  INFO(r.output);
  CHECK(r.exit_code == 0);
  CHECK(has(r.output, "warning: every point is beyond s_c = 1.5 m (the nearest is 2 m"));
  r = run("map --dataset " + wall.string() + " --method knn --s-c 4 --out " + (dir / "near.ot").string());
  CHECK(r.exit_code == 0);
  CHECK(!has(r.output, "warning"));
}

TEST_CASE("help text claims only what is true") {
  // The .ot holds the resolution and log-odds only: liboctomap reads back threshold 0.5 and hit 0.7.
  const auto r = run("map --help");
  CHECK(r.exit_code == 0);
  CHECK(!has(r.output, "stored in the .ot"));
  CHECK(has(r.output, "--shift") == false);  // --shift belongs to import, below
  CHECK(has(run("import cloud --help").output, "--shift"));
  CHECK(has(run("compare --help").output, "--allow-mixed"));
}

TEST_CASE("map --out x.bt is refused: the map is written as .ot, never .ot bytes under a .bt name") {
  const fs::path dir = test::scratch("robust_numbers_bt");
  const fs::path wall = wallDataset(dir, "wall");
  const auto r = run("map --dataset " + wall.string() + " --out " + (dir / "x.bt").string());
  requireRefused(r, {"--out", "x.bt", ".ot"});
  CHECK(!fs::exists(dir / "x.bt"));
}
