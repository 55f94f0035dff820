// "No input crashes, hangs or exhausts memory": each small input that crashed occsweep, hung it or made
// it allocate gigabytes, run through the real command. Each case checks the exit status, that the message names the
// file or flag, the size and the limit, that nothing partial is left, and the command's own peak memory (wait4's
// ru_maxrss of the child) below 200 MB. docs/robustness.md, "Limits and non-regular files".
//
// OCCSWEEP_TEST_CLI=/path/to/occsweep runs the same claims against another binary (the old one, to see them fail).
#include <catch2/catch.hpp>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <fstream>
#include <thread>

#include <fcntl.h>
#include <png.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <octomap/AbstractOcTree.h>

#include "occsweep/data/octree_file.hpp"
#include "test_helpers.hpp"

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

#if defined(__SANITIZE_ADDRESS__)
constexpr bool kSanitized = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool kSanitized = true;
#else
constexpr bool kSanitized = false;
#endif
#else
constexpr bool kSanitized = false;
#endif

constexpr long kPeakLimitKb = 200 * 1024;  // the peak allowed for every small input

struct Run {
  int exit_code = -1;    ///< -1 when killed by a signal or by the hang guard
  int signal = 0;
  bool hung = false;     ///< still running after the guard's timeout: killed
  long peak_rss_kb = 0;  ///< the child's own peak resident set (ru_maxrss)
  std::string output;    ///< stdout and stderr
};

/// Runs occsweep ARGS (a shell string) as its own process (exec'd by the shell, so wait4 measures occsweep itself).
/// `address_space_mb` caps the child's virtual memory so that an unbounded old binary fails fast instead of taking
/// the machine (not under sanitizers, which reserve terabytes). The guard kills a child still running after
/// `timeout_s`: a hang, reported as `hung`, never a timed assertion on a result.
Run runOccsweep(const std::string& args, long address_space_mb = 3072, int timeout_s = 120) {
  const fs::path out = occsweep::test::processScratch("limits_run_output") / "out.txt";
  const std::string cmd = "exec " + occsweep::test::cliUnderTest() + " " + args + " >" + out.string() + " 2>&1 </dev/null";
  const pid_t pid = ::fork();
  if (pid == 0) {
    if (!kSanitized && address_space_mb > 0) {
      const rlimit as{rlim_t(address_space_mb) << 20, rlim_t(address_space_mb) << 20};
      ::setrlimit(RLIMIT_AS, &as);
    }
    ::execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  Run r;
  int status = 0;
  rusage usage{};
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(timeout_s);
  while (::wait4(pid, &status, WNOHANG, &usage) == 0) {
    if (std::chrono::steady_clock::now() > deadline) {
      r.hung = true;
      ::kill(pid, SIGKILL);
      ::wait4(pid, &status, 0, &usage);
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  if (WIFEXITED(status)) r.exit_code = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) r.signal = WTERMSIG(status);
  r.peak_rss_kb = usage.ru_maxrss;
  std::ifstream in(out);
  r.output.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  return r;
}

/// The peak-memory claim; skipped under sanitizers, whose shadow memory makes any RSS bound meaningless.
void checkPeak(const Run& r) {
  INFO("peak RSS " << r.peak_rss_kb / 1024 << " MB");
  if (!kSanitized) CHECK(r.peak_rss_kb < kPeakLimitKb);
}

/// A refusal: exit 2 (no signal, no hang), and the message holds every one of `words`.
void checkRefused(const Run& r, std::initializer_list<std::string> words) {
  INFO(r.output);
  CHECK_FALSE(r.hung);
  CHECK(r.signal == 0);
  CHECK(r.exit_code == 2);
  for (const auto& w : words) CHECK(r.output.find(w) != std::string::npos);
  CHECK(r.output.find("Segmentation") == std::string::npos);
  checkPeak(r);
}

/// Files in `dir` whose name holds `.tmp-` or `.partial` (what a failed command must not leave).
std::vector<std::string> leftovers(const fs::path& dir) {
  std::vector<std::string> found;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    const auto name = e.path().filename().string();
    if (name.find(".tmp-") != std::string::npos || name.find(".partial") != std::string::npos) found.push_back(name);
  }
  return found;
}

/// The built-in scene, written once for the whole program (with the binary under test).
const fs::path& scene() {
  static const fs::path dir = [] {
    const fs::path d = occsweep::test::processScratch("limits_scene") / "scene";
    const Run r = runOccsweep("scene --out " + d.string());
    REQUIRE(r.exit_code == 0);
    return d;
  }();
  return dir;
}

json readJson(const fs::path& file) { return json::parse(std::ifstream(file)); }
void writeText(const fs::path& file, const std::string& text) { std::ofstream(file, std::ios::binary) << text; }

/// mapdiff finds the two maps equal: every voxel known in both (and some), none disagreeing.
void checkSameMap(const fs::path& a, const fs::path& b) {
  const Run diff = runOccsweep("mapdiff " + a.string() + " " + b.string());
  REQUIRE(diff.exit_code == 0);
  const json d = json::parse(diff.output.substr(diff.output.find('{')));
  CHECK(d.at("disagree") == 0);
  CHECK(d.at("known_only_a") == 0);
  CHECK(d.at("known_only_b") == 0);
  CHECK(d.at("known_both").get<std::uint64_t>() > 0);
}

/// knn-opt with k = 1..100000: 405 M combinations from a 1 MB file (old: 3.9 GB, then bad_alloc naming no file).
void writeManyKGrid(const fs::path& file) {
  json g = readJson(occsweep::test::sourceTree() / "sweeps" / "grids" / "knn-opt.json");
  g["name"] = "many-k";
  std::vector<int> k(100000);
  for (int i = 0; i < 100000; ++i) k[std::size_t(i)] = i + 1;
  g["parameters"]["k"] = k;
  writeText(file, g.dump());
}

/// A copy of the scene whose manifest is edited by `edit`.
fs::path editedScene(const fs::path& dir, const std::function<void(json&)>& edit) {
  const fs::path d = dir / "edited";
  fs::copy(scene(), d, fs::copy_options::recursive);
  json m = readJson(d / "manifest.json");
  edit(m);
  writeText(d / "manifest.json", m.dump());
  return d;
}

/// A grid file: octomap-opt with one parameter replaced.
fs::path gridFile(const fs::path& dir, const std::string& name, const std::function<void(json&)>& edit) {
  json g = readJson(occsweep::test::sourceTree() / "sweeps" / "grids" / "octomap-opt.json");
  g["name"] = name;
  edit(g);
  const fs::path file = dir / (name + ".json");
  writeText(file, g.dump(1));
  return file;
}

/// A real 16-bit greyscale PNG of constant pixels written with libpng: tiny on disk, `w * h * 2` bytes decoded.
void writeConstantPng(const fs::path& file, std::uint32_t w, std::uint32_t h, std::uint16_t value) {
  FILE* f = std::fopen(file.c_str(), "wb");
  REQUIRE(f);
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  png_init_io(png, f);
  png_set_compression_level(png, 9);
  png_set_IHDR(png, info, w, h, 16, PNG_COLOR_TYPE_GRAY, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  std::vector<png_byte> row(std::size_t(w) * 2);
  for (std::uint32_t u = 0; u < w; ++u) {
    row[2 * u] = png_byte(value >> 8);  // PNG is big-endian
    row[2 * u + 1] = png_byte(value & 0xff);
  }
  for (std::uint32_t v = 0; v < h; ++v) png_write_row(png, row.data());
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  std::fclose(f);
}

}  // namespace

TEST_CASE("k-NN maps with a large s_c or a fine resolution: a correct map or a refusal, never a crash") {
  const fs::path dir = occsweep::test::scratch("limits_knn");
  // Every scene point lies within 20 m of its origin, so s_c 20 and 81.05 must give the same map; 81.05 wrapped
  // the old 32-bit window volume (SIGSEGV), and the window's memory grew with the cube of s_c / resolution.
  const Run wide =
      runOccsweep("map --dataset " + scene().string() + " --method knn --s-c 81.05 --out " + (dir / "wide.ot").string());
  INFO(wide.output);
  CHECK(wide.signal == 0);
  REQUIRE(wide.exit_code == 0);
  checkPeak(wide);
  const Run near = runOccsweep("map --dataset " + scene().string() + " --method knn --s-c 20 --out " + (dir / "near.ot").string());
  REQUIRE(near.exit_code == 0);
  checkSameMap(dir / "wide.ot", dir / "near.ot");

  // A resolution of 0.00493 m: the scene's extent holds too many voxels for a window (or the region): refused by
  // name, with the size and the limit, before anything big is allocated; no map left.
  const Run fine = runOccsweep("map --dataset " + scene().string() + " --method knn --resolution 0.00493 --out " +
                            (dir / "fine.ot").string());
  checkRefused(fine, {"is more than the limit of", "--max-"});
  CHECK_FALSE(fs::exists(dir / "fine.ot"));
  CHECK(leftovers(dir).empty());

  // The same through sweep --engine direct on a one-map k-NN grid.
  json g = readJson(occsweep::test::sourceTree() / "sweeps" / "grids" / "knn-opt.json");
  g["name"] = "knn-one";
  for (const char* p : {"p_m", "p_m_out"}) g["parameters"][p] = {{"value", 0.38}};
  for (const char* p : {"p_u", "p_l"}) g["parameters"][p] = {{"value", 0.5}};
  writeText(dir / "knn-one.json", g.dump());
  const Run sweep = runOccsweep("sweep --dataset " + scene().string() + " --grid " + (dir / "knn-one.json").string() +
                             " --engine direct --s-c 81.05 --threads 1 --out " + (dir / "sweep.json").string());
  INFO(sweep.output);
  CHECK(sweep.signal == 0);
  CHECK(sweep.exit_code == 0);
  checkPeak(sweep);
}

TEST_CASE("grids past the combination limit are counted by Eq. 15 and refused before enumeration") {
  const fs::path dir = occsweep::test::scratch("limits_grid");
  // p_t by 1e-6 on octomap-opt: 19.2 M combinations (20 maps of 960,001 thresholds) (old: 3.9 GB, then SIGABRT).
  const fs::path fine = gridFile(dir, "fine-pt", [](json& g) { g["parameters"]["p_t"]["step"] = 0.000001; });
  const Run count = runOccsweep("grid count " + fine.string());
  INFO(count.output);
  CHECK(count.signal == 0);
  CHECK(count.exit_code == 0);
  CHECK(count.output.find("19200020 combinations (Eq. 15 closed form; not enumerated") != std::string::npos);
  checkPeak(count);

  const Run sweep = runOccsweep("sweep --dataset " + scene().string() + " --grid " + fine.string() + " --out " +
                             (dir / "r.json").string());
  checkRefused(sweep, {"grid fine-pt", "19200020", "is more than the limit of 2000000", "--max-combinations"});
  CHECK_FALSE(fs::exists(dir / "r.json"));
  CHECK(leftovers(dir).empty());
  // grid shards lists each group's ids, a permutation of the whole grid (old binary: 188 MB here, and 14 GB for a
  // grid of 1.8 billion combinations, no refusal).
  const Run shards = runOccsweep("grid shards " + fine.string());
  checkRefused(shards, {"grid fine-pt", "19200020", "is more than the limit of 2000000", "--max-combinations"});
  checkPeak(shards);

  // k-NN k = 1..100000 (old: 3.9 GB, then bad_alloc naming no file).
  writeManyKGrid(dir / "many-k.json");
  const Run list = runOccsweep("grid list " + (dir / "many-k.json").string());
  checkRefused(list, {"grid many-k", "405000000", "is more than the limit of", "--max-combinations"});
  const Run count_k = runOccsweep("grid count " + (dir / "many-k.json").string());
  INFO(count_k.output);
  CHECK(count_k.exit_code == 0);
  CHECK(count_k.output.find("405000000 combinations (Eq. 15 closed form") != std::string::npos);
  checkPeak(count_k);
}

TEST_CASE("merge does not trust grid.combinations of a results file whose grid is not found") {
  const fs::path dir = occsweep::test::scratch("limits_merge");
  // A real one-map sweep, then its header edited: an unknown grid claiming 3e8 combinations (old: 2.4 GB).
  const fs::path grid = gridFile(dir, "tiny", [](json& g) {
    g["parameters"]["p_h"] = {{"value", 0.74}};
    g["parameters"]["p_m"] = {{"value", 0.38}};
  });
  const Run sweep = runOccsweep("sweep --dataset " + scene().string() + " --grid " + grid.string() + " --threads 1 --out " +
                             (dir / "r.json").string());
  REQUIRE(sweep.exit_code == 0);
  json r = readJson(dir / "r.json");
  r["grid"]["name"] = "no-such-grid";
  r["grid"]["combinations"] = 300000000;
  writeText(dir / "claims.json", r.dump());
  const Run merge = runOccsweep("merge " + (dir / "claims.json").string() + " --out " + (dir / "merged.json").string());
  // Refused in bounded memory: the claim is checked against the maps the file holds (docs/results-format.md)
  // before any list of expected ids is made.
  checkRefused(merge, {"claims.json", "300000000"});
  CHECK_FALSE(fs::exists(dir / "merged.json"));
}

TEST_CASE("mapdiff refuses truncated, corrupt and explosive .ot files by name, in bounded memory") {
  const fs::path dir = occsweep::test::scratch("limits_ot");
  const Run map = runOccsweep("map --dataset " + scene().string() + " --method octomap --out " + (dir / "good.ot").string());
  REQUIRE(map.exit_code == 0);
  std::ifstream in(dir / "good.ot", std::ios::binary);
  const std::string good((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::size_t data = good.find("\ndata\n") + 6;
  REQUIRE(data > 6);

  SECTION("a good map against itself: no disagreement") {
    const Run same = runOccsweep("mapdiff " + (dir / "good.ot").string() + " " + (dir / "good.ot").string());
    INFO(same.output);
    REQUIRE(same.exit_code == 0);
    CHECK(same.output.find("\"disagree\": 0") != std::string::npos);
    CHECK(same.output.find("Reading") == std::string::npos);
  }
  SECTION("the bounded reader reads a good map exactly as liboctomap does") {
    const auto ours = occsweep::readOcTree(dir / "good.ot");
    std::unique_ptr<octomap::AbstractOcTree> theirs(octomap::AbstractOcTree::read((dir / "good.ot").string()));
    const auto* reference = dynamic_cast<const octomap::OcTree*>(theirs.get());
    REQUIRE(reference);
    CHECK(ours->getResolution() == reference->getResolution());
    CHECK(ours->size() == reference->size());
    std::size_t leaves = 0, differing = 0;
    for (auto it = reference->begin_leafs(); it != reference->end_leafs(); ++it, ++leaves) {
      const auto* node = ours->search(it.getKey(), it.getDepth());
      if (!node || node->getLogOdds() != it->getLogOdds()) ++differing;
    }
    CHECK(differing == 0);
    CHECK(leaves == ours->getNumLeafNodes());
    CHECK(leaves > 1000);
  }
  SECTION("truncated in the node stream") {
    writeText(dir / "cut.ot", good.substr(0, data + (good.size() - data) / 2));
    checkRefused(runOccsweep("mapdiff " + (dir / "good.ot").string() + " " + (dir / "cut.ot").string()),
                 {"cut.ot", "truncated"});
  }
  SECTION("0xff bytes after the header (every node claims 8 children)") {
    writeText(dir / "ff.ot", good.substr(0, data) + std::string(1 << 20, '\xff'));
    checkRefused(runOccsweep("mapdiff " + (dir / "ff.ot").string() + " " + (dir / "good.ot").string()), {"ff.ot"});
  }
  SECTION("a root without children: one node that expand() would make 8^16 voxels") {
    writeText(dir / "root.ot", good.substr(0, data) + std::string("\0\0\0\0\0", 5));
    checkRefused(runOccsweep("mapdiff " + (dir / "root.ot").string() + " " + (dir / "good.ot").string()),
                 {"root.ot", "281474976710656", "is more than the limit of", "--max-map-voxels"});
  }
  SECTION("a folder and a FIFO given as maps") {
    fs::create_directories(dir / "folder.ot");
    checkRefused(runOccsweep("mapdiff " + (dir / "folder.ot").string() + " " + (dir / "good.ot").string(), 3072, 20),
                 {"folder.ot", "is a folder"});
    REQUIRE(::mkfifo((dir / "fifo.ot").c_str(), 0600) == 0);
    checkRefused(runOccsweep("mapdiff " + (dir / "fifo.ot").string() + " " + (dir / "good.ot").string(), 3072, 20),
                 {"fifo.ot", "FIFO"});
  }
}

TEST_CASE("regions: the truth's box grown by a margin by default, and a region past the voxel limit is refused") {
  const fs::path dir = occsweep::test::scratch("limits_region");
  SECTION("import truth chooses the truth's bounding box grown by 0.5 m, and says so") {
    // A cloud with one far point (as a stereo cloud's disparity near zero): the points' box is 1 km long.
    writeText(dir / "cloud.xyz", "0 0 0\n1 1 1\n0.5 0.2 0.3\n0 0 1000\n");
    REQUIRE(runOccsweep("import cloud " + (dir / "cloud.xyz").string() + " --out " + (dir / "raw").string()).exit_code == 0);
    writeText(dir / "boxes.json", R"([{"min": [0, 0, 0], "max": [1, 1, 1]}])");
    const Run r = runOccsweep("import truth " + (dir / "boxes.json").string() + " --dataset " + (dir / "raw").string() +
                           " --out " + (dir / "ds").string());
    INFO(r.output);
    REQUIRE(r.exit_code == 0);
    const json region = readJson(dir / "ds" / "manifest.json").at("region");
    CHECK(region.at("min") == json::array({-0.5, -0.5, -0.5}));
    CHECK(region.at("max") == json::array({1.5, 1.5, 1.5}));
    CHECK(r.output.find("region (the truth's bounding box grown by 0.5 m)") != std::string::npos);
    CHECK(r.output.find("8000 voxels at 0.1 m") != std::string::npos);
  }
  SECTION("a region of 1e12 voxels is refused at once by map and sweep, naming the manifest, size and limit") {
    const fs::path d = editedScene(dir, [](json& m) {
      m["region"] = {{"min", {-500.0, -500.0, -500.0}}, {"max", {499.99, 499.99, 499.99}}};
    });
    const Run map = runOccsweep("map --dataset " + d.string() + " --method octomap --out " + (dir / "m.ot").string(), 3072, 60);
    checkRefused(map, {"manifest.json", "region", "1000000000000", "is more than the limit of", "--max-region-voxels"});
    CHECK_FALSE(fs::exists(dir / "m.ot"));
    const Run sweep = runOccsweep("sweep --dataset " + d.string() + " --grid octomap-opt --out " + (dir / "s.json").string(), 3072, 60);
    checkRefused(sweep, {"manifest.json", "1000000000000", "--max-region-voxels"});
    CHECK_FALSE(fs::exists(dir / "s.json"));
    CHECK(leftovers(dir).empty());
  }
}

TEST_CASE("images and manifests are bounded by pixels and points, counted before allocating") {
  const fs::path dir = occsweep::test::scratch("limits_pixels");
  SECTION("a real 8192 x 8192 16-bit PNG of ~130 KB that decodes to 128 MB") {
    writeConstantPng(dir / "big.png", 8192, 8192, 1000);
    CHECK(fs::file_size(dir / "big.png") < 200 * 1024);
    writeText(dir / "pose.txt", "0 0 0 0 0 0 1\n");
    const Run r = runOccsweep("import depth " + (dir / "big.png").string() + " --poses " + (dir / "pose.txt").string() +
                           " --fx 500 --fy 500 --cx 4096 --cy 4096 --out " + (dir / "ds").string());
    checkRefused(r, {"big.png", "8192x8192", "67108864", "is more than the limit of 8388608", "--max-image-pixels"});
    CHECK_FALSE(fs::exists(dir / "ds"));
    CHECK(leftovers(dir).empty());
  }
  SECTION("20,000 manifest entries naming one 24 KB scan") {
    const fs::path d = editedScene(dir, [](json& m) {
      json entry = m["scans"][0];
      entry["points"] = 2000;
      entry["file"] = "scans/one.f32";
      m["scans"] = json::array();
      for (int i = 0; i < 20000; ++i) m["scans"].push_back(entry);
    });
    std::vector<float> xyz;
    for (int i = 0; i < 2000; ++i) xyz.insert(xyz.end(), {float(i % 10) * 0.1f, float(i / 10 % 10) * 0.1f, 0.5f});
    std::ofstream(d / "scans" / "one.f32", std::ios::binary)
        .write(reinterpret_cast<const char*>(xyz.data()), std::streamsize(xyz.size() * sizeof(float)));
    REQUIRE(fs::file_size(d / "scans" / "one.f32") == 24000);
    const Run r = runOccsweep("map --dataset " + d.string() + " --method octomap --out " + (dir / "m.ot").string());
    checkRefused(r, {"manifest.json", "scans", "40000000", "is more than the limit of", "--max-points"});
    CHECK_FALSE(fs::exists(dir / "m.ot"));
  }
}

TEST_CASE("FIFOs, folders and symlink loops are refused by name wherever a file is read, never waited on") {
  const fs::path dir = occsweep::test::scratch("limits_fifo");
  REQUIRE(::mkfifo((dir / "fifo.json").c_str(), 0600) == 0);
  fs::create_directories(dir / "folder.json");
  fs::create_symlink("loop_b.json", dir / "loop_a.json");
  fs::create_symlink("loop_a.json", dir / "loop_b.json");

  SECTION("manifest.json a FIFO: map") {
    const fs::path d = editedScene(dir, [](json&) {});
    fs::remove(d / "manifest.json");
    REQUIRE(::mkfifo((d / "manifest.json").c_str(), 0600) == 0);
    checkRefused(runOccsweep("map --dataset " + d.string() + " --method octomap --out " + (dir / "m.ot").string(), 3072, 20),
                 {"manifest.json", "is a FIFO"});
  }
  SECTION("results files: FIFO, folder, symlink loop for results check and compare") {
    for (const char* cmd : {"results check", "compare"}) {
      checkRefused(runOccsweep(std::string(cmd) + " " + (dir / "fifo.json").string(), 3072, 20), {"fifo.json", "is a FIFO"});
      const Run folder = runOccsweep(std::string(cmd) + " " + (dir / "folder.json").string(), 3072, 20);
      checkRefused(folder, {"folder.json", "is a folder"});
      CHECK(folder.output.find("underflow") == std::string::npos);
      const Run loop = runOccsweep(std::string(cmd) + " " + (dir / "loop_a.json").string(), 3072, 20);
      checkRefused(loop, {"loop_a.json", "symbolic link loop"});
      CHECK(loop.output.find("missing") == std::string::npos);
    }
  }
  SECTION("a ranking given to cluster select that is a FIFO") {
    checkRefused(runOccsweep("cluster select --out " + (dir / "selected").string() + " " + (dir / "fifo.json").string(),
                             3072, 20),
                 {"fifo.json", "is a FIFO"});
    CHECK_FALSE(fs::exists(dir / "selected"));
  }
  SECTION("a grid file that is a FIFO or a folder") {
    checkRefused(runOccsweep("grid count " + (dir / "fifo.json").string(), 3072, 20), {"fifo.json", "is a FIFO"});
    checkRefused(runOccsweep("grid count " + (dir / "folder.json").string(), 3072, 20), {"folder.json", "is a folder"});
  }
}

TEST_CASE("a FIFO at an output's name is refused by name at once, with or without --force, never opened") {
  // Old binary: `plot ... --out fig.png --force` opened the FIFO to look for occsweep's mark in it and waited for a
  // writer for ever; compare's tables on a FIFO were refused as "not occsweep's", saying nothing of what it is.
  const fs::path dir = occsweep::test::scratch("limits_fifo_outputs");
  const std::string golden = (occsweep::test::sourceTree() / "results/builtin/octomap-opt.json").string();
  for (const char* name : {"fig.png", "fig.pdf", "fig.svg", "table", "m.ot"})
    REQUIRE(::mkfifo((dir / name).c_str(), 0600) == 0);
  const std::string table = (dir / "table").string();
  for (const std::string force : {"", " --force"}) {
    for (const std::string figure : {"fig.png", "fig.pdf", "fig.svg"})
      checkRefused(runOccsweep("plot budget " + golden + " --out " + (dir / figure).string() + force, 3072, 20),
                   {figure + ": is a FIFO (named pipe)"});
    checkRefused(runOccsweep("plot budget " + golden + " --out " + (dir / "b.png").string() + " --json " + table + force,
                             3072, 20),
                 {"table: is a FIFO (named pipe)"});
    for (const std::string flag : {"--json", "--csv", "--markdown", "--latex"})
      checkRefused(runOccsweep("compare " + golden + " " + flag + " " + table + force, 3072, 20),
                   {"table: is a FIFO (named pipe)"});
    checkRefused(runOccsweep("map --dataset " + scene().string() + " --out " + (dir / "m.ot").string() + force, 3072, 20),
                 {"m.ot: is a FIFO (named pipe)"});
  }
  CHECK_FALSE(fs::exists(dir / "b.png"));
}

TEST_CASE("bad_alloc never escapes as an abort: a raised limit meeting a memory cap ends in a message, exit 2") {
  if (kSanitized) {
    WARN("skipped under sanitizers: they cannot run under an address-space cap");
    return;
  }
  const fs::path dir = occsweep::test::scratch("limits_bad_alloc");
  writeManyKGrid(dir / "many-k.json");
  // 1 GB of address space: 45 M maps (405 M combinations) cannot be enumerated once the limit is raised past them.
  const Run r = runOccsweep("grid list --max-combinations 1000000000 " + (dir / "many-k.json").string(), 1024);
  INFO(r.output.substr(0, 2000));
  CHECK(r.signal == 0);
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("out of memory while running `occsweep grid`") != std::string::npos);
}

TEST_CASE("scene bounds the product of its sizes by the points limit, and its noise, before any work") {
  // Old binary: --scans 100000 --width 100000 --height 100000 ran unbounded (each option was capped, not their
  // product), and --noise 1e300 wrote a data set of infinite coordinates, exit 0.
  const fs::path dir = occsweep::test::processScratch("limits_scene");
  const Run big = runOccsweep("scene --scans 100000 --width 100000 --height 100000 --out " + (dir / "big").string());
  checkRefused(big, {"the scene's rays (--scans x --width x --height): 1000000000000000 is more than the limit of",
                     "--max-points"});
  CHECK_FALSE(fs::exists(dir / "big"));
  checkRefused(runOccsweep("scene --noise 1e300 --out " + (dir / "noisy").string()),
               {"--noise must be a number in [0, 1000], got 1e300"});
  CHECK_FALSE(fs::exists(dir / "noisy"));
  // At the limit, raised: it runs (8 x 32 x 24 = 6,144 rays under --max-points 6144).
  const Run at = runOccsweep("scene --scans 8 --width 32 --height 24 --max-points 6144 --out " + (dir / "at").string());
  INFO(at.output);
  CHECK(at.exit_code == 0);
  checkRefused(runOccsweep("scene --scans 8 --width 32 --height 24 --max-points 6143 --out " + (dir / "over").string()),
               {"6144 is more than the limit of 6143"});
  CHECK(leftovers(dir).empty());
}

TEST_CASE("neighbour searches a parameter made quadratic: ROR's radius runs in time, SOR's and k-NN's k past the "
          "neighbour-distance limit are refused at once") {
  // Finding H4: on one 200,000-point scan, map --method ror-octomap --radius 100 and --method sor-octomap --k 100000
  // ran silently past 100 s (every pair measured; k nearest kept in arrays sorted by shifting), within the methods'
  // bounds. docs/methods.md, "Neighbour searches". The guard kills a run still going after 60 s: `hung`.
  const fs::path dir = occsweep::test::processScratch("limits_neighbours");
  const std::string scan = (dir / "scan").string();
  const Run made = runOccsweep("scene --scans 1 --width 640 --height 480 --out " + scan);
  REQUIRE(made.exit_code == 0);
  REQUIRE(made.output.find("203094 points") != std::string::npos);
  // Radius 100 m: every point is every other's neighbour, none is removed, so the map is plain OctoMap's.
  const Run ror = runOccsweep("map --dataset " + scan + " --method ror-octomap --radius 100 --out " +
                              (dir / "ror.ot").string(), 3072, 60);
  INFO(ror.output);
  CHECK_FALSE(ror.hung);
  REQUIRE(ror.exit_code == 0);
  checkPeak(ror);
  const Run plain = runOccsweep("map --dataset " + scan + " --method octomap --out " + (dir / "octomap.ot").string());
  REQUIRE(plain.exit_code == 0);
  checkSameMap(dir / "ror.ot", dir / "octomap.ot");
  // k 100000: 203,094 x 100,000 neighbour distances, past the limit of 2^29: refused before any search, by flag.
  for (const std::string method : {"sor-octomap", "knn"}) {
    const fs::path out = dir / (method + ".ot");
    checkRefused(runOccsweep("map --dataset " + scan + " --method " + method + " --k 100000 --out " + out.string(),
                             3072, 60),
                 {method + ": k 100000", "is more than the limit of 536870912", "--max-neighbour-distances"});
    CHECK_FALSE(fs::exists(out));
  }
  json g = readJson(occsweep::test::sourceTree() / "sweeps" / "grids" / "sor-octomap-opt.json");
  g["name"] = "sor-k";
  g["parameters"]["k"] = {100000};
  writeText(dir / "sor-k.json", g.dump());
  checkRefused(runOccsweep("sweep --dataset " + scan + " --grid " + (dir / "sor-k.json").string() + " --out " +
                           (dir / "sor.json").string(), 3072, 60),
               {"sor-octomap: k 100000 on a scan of 203094 points", "--max-neighbour-distances"});
  CHECK_FALSE(fs::exists(dir / "sor.json"));
  // The flag moves the limit: the default k 50 is 10,154,700 distances.
  checkRefused(runOccsweep("map --dataset " + scan + " --method sor-octomap --max-neighbour-distances 10154699 --out " +
                           (dir / "low.ot").string()),
               {"10154700 is more than the limit of 10154699"});
  CHECK(leftovers(dir).empty());
}

TEST_CASE("worker threads are bounded on every command that takes them: a refusal naming the flag, never a crash") {
  // Old binary: --threads 1073741824 or 2147483647 ended map --method knn and sweep in SIGSEGV (leaving the partial
  // results), and --threads 1000000 cost 550 MB on the built-in scene before any work.
  const fs::path dir = occsweep::test::processScratch("limits_threads");
  const std::string data = " --dataset " + scene().string();
  const std::string grid = (occsweep::test::sourceTree() / "sweeps" / "grids" / "octomap-opt.json").string();
  for (const char* threads : {"1025", "1000000", "1073741824", "2147483647", "99999999999"}) {
    const std::string t = threads;
    const struct {
      std::string args, output;
    } cases[] = {
        {"map --method knn" + data + " --threads " + t + " --out " + (dir / "m.ot").string(), "m.ot"},
        {"sweep" + data + " --grid " + grid + " --threads " + t + " --out " + (dir / "r.json").string(), "r.json"},
        {"reproduce --scale ci --no-figures --threads " + t + " --out " + (dir / "repro").string(), "repro"},
        {"dataset generate --name building-plain-I --threads " + t + " --out " + (dir / "gen").string(), "gen"},
        {"cluster plan --experiment sweep --dataset " + scene().string() + " --grid " + grid + " --threads " + t +
             " --out " + (dir / "plan").string(), "plan"},
    };
    for (const auto& c : cases) {
      INFO(c.args);
      const Run r = runOccsweep(c.args);
      checkRefused(r, {"--threads must be an integer from 0 to 1024, got " + t});
      CHECK_FALSE(fs::exists(dir / c.output));
    }
    INFO("run-local --threads " << t);
    checkRefused(runOccsweep("cluster run-local " + (dir / "no-plan").string() + " --threads " + t),
                 {"--threads must be an integer from 1 to 1024, got " + t});
  }
  CHECK(leftovers(dir).empty());
  // The bound itself runs, in bounded memory, and gives the map one thread gives (docs/robustness.md).
  const Run at_bound = runOccsweep("map --method knn" + data + " --threads 1024 --out " + (dir / "at.ot").string());
  INFO(at_bound.output);
  CHECK(at_bound.exit_code == 0);
  checkPeak(at_bound);
  const Run one = runOccsweep("map --method knn" + data + " --threads 1 --out " + (dir / "one.ot").string());
  CHECK(one.exit_code == 0);
  CHECK(occsweep::test::bytesOf(dir / "at.ot") == occsweep::test::bytesOf(dir / "one.ot"));
}

TEST_CASE("cluster plan --pcs-count past its limit is refused by the flag, in bounded memory, writing nothing") {
  // Old binary: --pcs-count 100000000 expanded every id into one argv string and plan.json, 1.75 GB and more (under
  // this test's 1 GB cap: out of memory, blaming a raised flag). docs/cluster.md, "Options".
  const fs::path dir = occsweep::test::processScratch("limits_pcs_count");
  const Run r = runOccsweep("cluster plan --out " + (dir / "p").string() + " --pcs-count 100000000", 1024);
  checkRefused(r, {"--pcs-count 100000000 is more than the limit of 100000"});
  CHECK_FALSE(fs::exists(dir / "p"));
  // Within the limit but in one block, {pcs} would not fit one command-line argument: refused, asking for --blocks.
  const Run one = runOccsweep("cluster plan --out " + (dir / "p").string() + " --pcs-count 100000 --blocks 1 "
                              "--unranked", 1024);
  checkRefused(one, {"--pcs-count 100000 in --blocks 1", "131071 bytes", "raise --blocks"});
  CHECK_FALSE(fs::exists(dir / "p"));
  // At the limit, in enough blocks, the plan is written (each generation task gets its block's ids).
  const Run at = runOccsweep("cluster plan --out " + (dir / "p").string() + " --name one --pcs-count 100000 "
                             "--blocks 16 --sets pcs-0000 --group-set pcs-0000", 1024);
  INFO(at.output);
  CHECK(at.exit_code == 0);
  checkPeak(at);
  CHECK(fs::exists(dir / "p" / "plan.json"));
}

namespace {

/// An OctoMap grid of `maps` maps (p_h values) whose p_t runs by `p_t_step`: combinations = maps x thresholds.
void writeFinePtGrid(const fs::path& file, int maps, const char* p_t_step) {
  std::ofstream(file) << R"({"name": "fine-pt", "method": "octomap", "parameters": {"p_max": {"value": 0.98},
    "p_min": {"value": 0.02}, "p_h": {"min": 0.5, "max": )" << 0.5 + 0.12 * (maps - 1) << R"(, "step": 0.12},
    "p_m": {"value": 0.2}, "p_t": {"step": )" << p_t_step << "}}}";
}

}  // namespace

TEST_CASE("sweep refuses a JSON --out past 200,000 combinations at its start, pointing at --out NAME.db") {
  // Old binary: this 200-byte grid of 1,920,002 combinations (2 maps, p_t by 0.000001; under the 2 M default limit)
  // took 3.57 GB to sweep into JSON (under this test's 1 GB cap: out of memory, blaming a flag nobody raised).
  const fs::path dir = occsweep::test::processScratch("limits_json_out");
  writeFinePtGrid(dir / "fine.json", 2, "0.000001");
  const std::string sweep = "sweep --quiet --dataset " + scene().string() + " --grid " + (dir / "fine.json").string();
  const Run r = runOccsweep(sweep + " --out " + (dir / "fine-results.json").string(), 1024);
  checkRefused(r, {"--out " + (dir / "fine-results.json").string(), "at most 200000 combinations", "writes 1920002",
                   "use --out NAME.db"});
  CHECK_FALSE(fs::exists(dir / "fine-results.json"));
  CHECK(leftovers(dir).empty());
  // The selection counts, not the whole grid: a quarter of 4 maps x 60,001 thresholds fits in JSON.
  writeFinePtGrid(dir / "four.json", 4, "0.000016");
  const std::string four = "sweep --quiet --dataset " + scene().string() + " --grid " + (dir / "four.json").string();
  const Run quarter = runOccsweep(four + " --shard 0/4 --out " + (dir / "q.json").string(), 1024);
  INFO(quarter.output);
  CHECK(quarter.exit_code == 0);
  CHECK(fs::exists(dir / "q.json"));
  const Run whole = runOccsweep(four + " --out " + (dir / "w.json").string(), 1024);
  checkRefused(whole, {"writes 240004", "use --out NAME.db"});
  CHECK_FALSE(fs::exists(dir / "w.json"));
}

TEST_CASE("merge into JSON past 200,000 combinations is refused from the first header, pointing at --out NAME.db") {
  // Old binary: two store shards of 1,920,002 combinations merged into one JSON in memory (past this test's 1 GB cap:
  // out of memory); the sweep's own limit did not hold for merge.
  const fs::path dir = occsweep::test::processScratch("limits_merge_json");
  writeFinePtGrid(dir / "fine.json", 2, "0.000001");
  const std::string sweep = "sweep --quiet --dataset " + scene().string() + " --grid " + (dir / "fine.json").string();
  for (const char* shard : {"0", "1"}) {
    // Old binary: 204 MB for this shard of one map (and 352 MB for the whole grid).
    const Run s = runOccsweep(sweep + " --shard " + shard + "/2 --out " + (dir / ("s" + std::string(shard) + ".db")).string(),
                              1024);
    REQUIRE(s.exit_code == 0);
    checkPeak(s);
  }
  const std::string shards = (dir / "s0.db").string() + " " + (dir / "s1.db").string();
  const Run r = runOccsweep("merge " + shards + " --out " + (dir / "m.json").string(), 1024);
  checkRefused(r, {"--out " + (dir / "m.json").string(), "at most 200000 combinations",
                   "the merge of 2 files writes 1920002", "use --out NAME.db"});
  CHECK_FALSE(fs::exists(dir / "m.json"));
  CHECK(leftovers(dir).empty());
  // Into a store the same merge is written batch by batch.
  const Run store = runOccsweep("merge " + shards + " --out " + (dir / "m.db").string(), 1024);
  INFO(store.output);
  CHECK(store.exit_code == 0);
  checkPeak(store);
  // And checked in its own memory (old binary: 2.49 GB for `results check` of the 1,920,002 combinations).
  const Run check = runOccsweep("results check " + (dir / "m.db").string(), 1024);
  INFO(check.output);
  CHECK(check.exit_code == 0);
  checkPeak(check);
  // compare checks as much and keeps each map's parameters and AUC, not its thresholds (old binary: their memory
  // kept, 170 MB against 125 MB for `results check`).
  const Run compare = runOccsweep("compare " + (dir / "m.db").string(), 1024);
  INFO(compare.output);
  CHECK(compare.exit_code == 0);
  INFO("compare peak RSS " << compare.peak_rss_kb / 1024 << " MB, results check " << check.peak_rss_kb / 1024 << " MB");
  if (!kSanitized) CHECK(compare.peak_rss_kb < check.peak_rss_kb + 10 * 1024);
}

TEST_CASE("results export into JSON past 200,000 combinations is refused as sweep refuses it, pointing at --out "
          "NAME.db") {
  // Old binary: this store of one map of 240,001 thresholds exported to JSON, exit 0: a JSON results file that no
  // sweep writes, which every reader then reads whole.
  const fs::path dir = occsweep::test::processScratch("limits_export_json");
  writeFinePtGrid(dir / "one.json", 1, "0.000004");
  const fs::path store = dir / "s.db", json_out = dir / "e.json";
  const Run s = runOccsweep("sweep --quiet --dataset " + scene().string() + " --grid " + (dir / "one.json").string() +
                            " --out " + store.string(), 1024);
  REQUIRE(s.exit_code == 0);
  const Run r = runOccsweep("results export " + store.string() + " --out " + json_out.string(), 1024);
  checkRefused(r, {"--out " + json_out.string() + ": a JSON results file holds at most 200000 combinations and the "
                   "export of " + store.string() + " writes 240001", "use --out NAME.db"});
  CHECK_FALSE(fs::exists(json_out));
  CHECK(leftovers(dir).empty());
  // CSV is written row by row and read by other programs: not bounded by it.
  const Run csv = runOccsweep("results export " + store.string() + " --out " + (dir / "e.csv").string(), 1024);
  INFO(csv.output);
  CHECK(csv.exit_code == 0);
}

namespace {

/// A JSON object of about `megabytes` MB holding one array of [1,2] pairs, as a user's data file might: nlohmann's
/// tree of it takes about 18 times its bytes.
void writeBigJson(const fs::path& file, int megabytes) {
  std::string pairs;
  while (pairs.size() < (std::size_t(1) << 20)) pairs += "[1,2],";
  std::ofstream out(file, std::ios::binary);
  out << "{\"data\": [";
  for (int i = 0; i < megabytes; ++i) out << pairs;
  out << "[1,2]]}";
}

}  // namespace

TEST_CASE("a JSON file of 100 MB at an output or as an input is refused, or ends in the out-of-memory message, never "
          "an abort") {
  // Old binary, under this test's 1 GB cap: each command below parsed the whole file into nlohmann's tree, ran out
  // of memory, and again while that tree was freed during unwinding (its destructor allocates): std::terminate,
  // "terminate called after throwing an instance of 'std::bad_alloc'", exit 134.
  if (kSanitized) {
    WARN("skipped under sanitizers: they cannot run under an address-space cap");
    return;
  }
  const fs::path dir = occsweep::test::processScratch("limits_big_json");
  const fs::path big = dir / "big.json";
  writeBigJson(big, 100);
  const std::uintmax_t size = fs::file_size(big);
  const std::string sweep = "sweep --quiet --dataset " + scene().string() + " --grid octomap-opt --out ";
  REQUIRE(runOccsweep(sweep + (dir / "r.json").string()).exit_code == 0);
  // At an output, whose it is comes from its first bytes ("format"): never read whole, and not replaced.
  for (const std::string& command : {"merge " + (dir / "r.json").string() + " --out " + big.string() + " --force",
                                     sweep + big.string()}) {
    INFO(command);
    checkRefused(runOccsweep(command, 1024), {big.string() + ": exists and is not occsweep's results file"});
    CHECK(fs::file_size(big) == size);
  }
  // The same file as a map's settings without their map (what an interrupted `map` leaves): not occsweep's.
  fs::create_hard_link(big, dir / "m.ot.json");
  checkRefused(runOccsweep("map --dataset " + scene().string() + " --method octomap --out " + (dir / "m.ot").string(),
                           1024),
               {(dir / "m.ot.json").string() + ": exists: occsweep replaces nothing unless asked"});
  CHECK_FALSE(fs::exists(dir / "m.ot"));
  fs::remove(dir / "m.ot.json");
  {  // As an input within the limit, its tree past the cap: main's out-of-memory message, exit 2.
    const Run check = runOccsweep("results check " + big.string(), 1024);
    INFO(check.output.substr(0, 2000));
    CHECK(check.signal == 0);
    CHECK(check.exit_code == 2);
    CHECK(check.output.find("out of memory while running `occsweep results` on " + big.string()) != std::string::npos);
  }
  // Past the limit: refused by its size before a byte is read.
  checkRefused(runOccsweep("results check " + big.string() + " --max-json-bytes 50000000", 1024),
               {big.string() + ": bytes of JSON: " + std::to_string(size) + " is more than the limit of 50000000",
                "--max-json-bytes"});
  fs::remove(big);
  // The default limit, 128 MiB (2^27), on a file one byte longer (sparse: nothing to write).
  { std::ofstream(big) << ""; }
  fs::resize_file(big, (std::uintmax_t(1) << 27) + 1);
  checkRefused(runOccsweep("compare " + big.string(), 1024),
               {big.string() + ": bytes of JSON: 134217729 is more than the limit of 134217728", "--max-json-bytes"});
  fs::remove(big);
  CHECK(leftovers(dir).empty());
}

// docs/robustness.md, "Limits": a replay batch holds at most 2^18 thresholds, so 3 maps of 96,001 are cut into a
// batch of 2 and one of 1; the cut batches count exactly what the direct engine builds.
TEST_CASE("replay batches cut at their thresholds count what the direct engine counts") {
  const fs::path dir = occsweep::test::processScratch("limits_batch_cut");
  writeFinePtGrid(dir / "cut.json", 3, "0.00001");
  const std::string sweep = "sweep --quiet --dataset " + scene().string() + " --grid " + (dir / "cut.json").string();
  for (const char* truth : {"full", "observable"}) {
    INFO("truth " << truth);
    const std::string replay = (dir / (std::string("replay-") + truth + ".db")).string();
    const std::string direct = (dir / (std::string("direct-") + truth + ".db")).string();
    REQUIRE(runOccsweep(sweep + " --truth " + truth + " --out " + replay, 1024).exit_code == 0);
    REQUIRE(runOccsweep(sweep + " --truth " + truth + " --engine direct --out " + direct, 1024).exit_code == 0);
    const Run diff = runOccsweep("results diff " + direct + " " + replay, 1024);
    INFO(diff.output);
    CHECK(diff.exit_code == 0);
  }
}

TEST_CASE("out of memory names the command's inputs and blames a limit flag only when one was raised") {
  // Old binary: "lower the one whose flag you raised" with no flag raised, and "on these inputs" naming none.
  if (kSanitized) {
    WARN("skipped under sanitizers: they cannot run under an address-space cap");
    return;
  }
  const fs::path dir = occsweep::test::processScratch("limits_oom_message");
  // 1,939,402 maps-and-thresholds (under the default 2 M): counting them needs more than a 100 MB address space.
  std::ofstream(dir / "many.json") << R"({"name": "many", "method": "octomap", "parameters": {"p_max": {"value": 0.98},
    "p_min": {"value": 0.02}, "p_h": {"min": 0.5, "max": 0.98, "step": 0.00005},
    "p_m": {"min": 0.02, "max": 0.38, "step": 0.0036}, "p_t": {"step": 0.96}}})";
  const std::string grid = (dir / "many.json").string();
  Run r = runOccsweep("grid count " + grid, 100);
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("out of memory while running `occsweep grid` on " + grid) != std::string::npos);
  CHECK(r.output.find("no limit was raised") != std::string::npos);
  CHECK(r.output.find("you raised") == std::string::npos);
  r = runOccsweep("grid count --max-combinations 3000000 " + grid, 100);
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("lower the limit you raised (--max-combinations)") != std::string::npos);
}

TEST_CASE("a grid of 530 million combinations is counted exactly without enumerating it, and one shard of 2,000 is "
          "swept in its own memory into a store of exactly its maps") {
  // Old binary: `grid count` printed Eq. 15 only for k-NN and OctoMap by name, and a sweep of one shard enumerated
  // the whole grid first (a 398 M-combination grid ran out of memory at a 3 GB cap, 2.7 GB reached).
  const fs::path dir = occsweep::test::scratch("limits_huge_grid");
  std::ofstream(dir / "huge.json") << R"({"name": "huge", "method": "knn", "parameters": {
    "p_max": {"min": 0.50, "max": 0.98, "step": 0.04}, "p_min": {"min": 0.02, "max": 0.38, "step": 0.06},
    "p_m": {"min": 0.02, "max": 0.38, "step": 0.03}, "p_m_out": {"min": 0.02, "max": 0.38, "step": 0.03},
    "p_u": {"min": 0.02, "max": 0.98, "step": 0.02}, "p_l": {"min": 0.02, "max": 0.98, "step": 0.02},
    "p_t": {"step": 0.02}, "k": [1, 3, 5, 7]}})";
  // The oracle, from docs/grids.md alone: every value in hundredths, the relations p_u >= p_l, p_m >= p_min,
  // p'_m >= p_m, and p_t from p_min to p_max by 0.02.
  std::uint64_t pairs = 0, maps = 0, combinations = 0;
  for (int u = 2; u <= 98; u += 2)
    for (int l = 2; l <= u; l += 2) ++pairs;
  for (int max = 50; max <= 98; max += 4)
    for (int min = 2; min <= 38; min += 6)
      for (int m = min + (3 - (min - 2) % 3) % 3; m <= 38; m += 3)
        for (int out = m; out <= 38; out += 3) ++maps, combinations += std::uint64_t((max - min) / 2 + 1);
  maps *= 4 * pairs, combinations *= 4 * pairs;
  REQUIRE(combinations > 398'000'000);

  const Run count = runOccsweep("grid count " + (dir / "huge.json").string());
  INFO(count.output);
  CHECK(count.exit_code == 0);
  CHECK(count.output.find(std::to_string(combinations) + " combinations (Eq. 15 closed form") != std::string::npos);
  checkPeak(count);

  const Run sweep = runOccsweep("sweep --dataset " + scene().string() + " --grid " + (dir / "huge.json").string() +
                                " --shard 0/2000 --quiet --out " + (dir / "s0.db").string(), 3072, 600);
  INFO(sweep.output);
  CHECK(sweep.exit_code == 0);
  INFO("sweep peak RSS " << sweep.peak_rss_kb / 1024 << " MB");
  if (!kSanitized) CHECK(sweep.peak_rss_kb < 500 * 1024);
  // Shard 0 of 2,000 contiguous blocks of the maps, the first (maps mod 2,000) one longer (docs/grids.md).
  const std::uint64_t share = maps / 2000 + (maps % 2000 > 0 ? 1 : 0);
  const char* grids = std::getenv("OCCSWEEP_GRIDS");
  const std::string before = grids ? grids : "";
  ::setenv("OCCSWEEP_GRIDS", dir.c_str(), 1);  // `results check` finds the grid by name: every map checked
  const Run check = runOccsweep("results check " + (dir / "s0.db").string(), 3072, 600);
  if (grids) ::setenv("OCCSWEEP_GRIDS", before.c_str(), 1);
  else ::unsetenv("OCCSWEEP_GRIDS");
  INFO(check.output);
  CHECK(check.exit_code == 0);
  CHECK(check.output.find("complete, " + std::to_string(share) + " maps") != std::string::npos);
  CHECK(check.output.find("not checked") == std::string::npos);
  checkPeak(check);
}

TEST_CASE("a user's file of gigabytes without a line break at a sweep's partial-log name is refused without reading "
          "it whole") {
  // Old binary: its first line was read whole (std::getline) to look for occsweep's header, 512 MB into memory.
  const fs::path dir = occsweep::test::processScratch("limits_partial_line");
  const fs::path partial = dir / "r.json.partial.jsonl";
  fs::remove(partial);
  fs::remove(dir / "r.json");
  { std::ofstream(partial) << ""; }
  fs::resize_file(partial, std::uintmax_t(512) << 20);  // 512 MB of zero bytes, no line break (sparse on disk)
  const Run r = runOccsweep("sweep --dataset " + scene().string() + " --grid octomap-opt --quiet --out " +
                            (dir / "r.json").string());
  checkRefused(r, {"r.json.partial.jsonl: not a partial log of occsweep's (its first line is not a sweep's header)",
                   "never resumes from, replaces or removes it"});
  CHECK(fs::file_size(partial) == std::uintmax_t(512) << 20);
  fs::remove(partial);
}
