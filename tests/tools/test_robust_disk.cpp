// Full disk: every command that writes, with its output on a small full tmpfs, exits 2 saying "no space
// left on device" and naming the file, and leaves nothing behind: no temporary, nothing under the final name
// (docs/io.md, "Outputs and --force"). Needs `mount` (CI runs as root); skipped otherwise.
#include <catch2/catch.hpp>
#include <algorithm>
#include <sys/mount.h>

#include "robust_outputs_helpers.hpp"

namespace fs = std::filesystem;
using namespace occsweep::test;

namespace {

/// A 256 KiB tmpfs at `dir`, unmounted at the end of the scope.
struct SmallDisk {
  fs::path dir;
  bool mounted = false;
  explicit SmallDisk(fs::path d) : dir(std::move(d)) {
    fs::create_directories(dir);
    mounted = ::mount("tmpfs", dir.c_str(), "tmpfs", 0, "size=256k") == 0;
  }
  ~SmallDisk() {
    if (mounted) ::umount(dir.c_str());
  }
  /// Fills the disk but `free_bytes` with a file of the test's own (`filler`).
  void fill(std::size_t free_bytes) {
    fs::remove(dir / "filler");
    std::ofstream out(dir / "filler", std::ios::binary);
    const std::string block(4096, 'x');
    while (out.write(block.data(), std::streamsize(block.size()))) out.flush();
    out.close();
    fs::resize_file(dir / "filler", fs::file_size(dir / "filler") - free_bytes);
  }
};

}  // namespace

TEST_CASE("every command writing to a full disk says no space left, names the file and leaves nothing", "[disk]") {
  const fs::path dir = scratch("robust_disk");
  REQUIRE(runIn(dir, "scene --scans 8 --width 64 --height 48 --out scene").exit_code == 0);
  writeTinyGrid(dir / "tiny.json");
  REQUIRE(runIn(dir, "sweep --dataset scene --grid tiny.json --quiet --out r.json").exit_code == 0);
  fs::create_directories(dir / "ds/pcs-0000");
  std::ofstream(dir / "ds/ranking.json") << R"({"format": "occsweep-pointcloud-ranking",
    "sets": [{"folder": "pcs-0000", "id": 0, "naive": {"fdr": 0.1, "tpr": 0.9}}]})";
  std::ofstream(dir / "truth.json") << R"({"boxes": [{"min": [0, 0, 0], "max": [1, 1, 1]}]})";
  {
    std::ofstream out(dir / "a.xyz");
    for (int i = 0; i < 3000; ++i) out << 1 + 0.001 * i << ' ' << 0.5 << ' ' << 0.0007 * i << '\n';
  }
  SmallDisk disk(dir / "disk");
  if (!disk.mounted) {
    WARN("mount -t tmpfs is not permitted here (not root?): full-disk test skipped");
    return;
  }
  struct Case {
    std::string args, file;  // the command (output under disk/) and the file its message must name
    bool over_a_page = true;  // false: the output fits the one free page, and is written (the comparison)
    bool stereo = false;      // a command of the stereo tools (absent when occsweep is built without them)
  };
  const bool have_stereo = runIn(dir, "dataset --help").exit_code == 0;
  const std::vector<Case> cases = {
      {"scene --scans 8 --width 64 --height 48 --out disk/out", "disk/out"},
      {"import cloud a.xyz --out disk/out", "disk/out"},
      {"map --dataset scene --method octomap --out disk/m.ot", "disk/m.ot"},
      {"sweep --dataset scene --grid tiny.json --quiet --out disk/r.json", "disk/r.json"},
      {"merge r.json --out disk/m.json", "disk/m.json"},
      {"compare r.json --json disk/c.json", "disk/c.json", false},
      {"import truth truth.json --dataset scene --out disk/out", "disk/out"},
      {"dataset generate --name parking-plain-I --scale ci --out disk/gen", "disk/gen", true, true},
      {"reproduce --scale ci --no-figures --out disk/repro", "disk/repro", true, true},
      {"cluster select ds/ranking.json --out disk/sel", "disk/sel", false},
      {"cluster plan --out disk/plan --experiment sweep --dataset scene --sets . --grid tiny.json:1", "disk/plan",
       false},
  };
  // Full, then one page free: the write fails at its first byte, or in the middle of the output.
  for (const std::size_t free_bytes : {std::size_t(0), std::size_t(4096)}) {
    for (const auto& c : cases) {
      if ((free_bytes > 0 && !c.over_a_page) || (c.stereo && !have_stereo)) continue;
      disk.fill(free_bytes);
      const CommandResult r = runIn(dir, c.args);
      INFO(c.args << " with " << free_bytes << " bytes free\n" << r.output);
      CHECK(r.exit_code == 2);
      CHECK(r.output.find("no space left on device") != std::string::npos);
      CHECK(r.output.find(c.file) != std::string::npos);
      fs::remove(disk.dir / "filler");
      // No temporary, no partial output; a sweep's partial log only when it keeps finished maps, and says so.
      const fs::path log = disk.dir / "r.json.partial.jsonl";
      if (r.output.find("maps finished are kept in disk/r.json.partial.jsonl") != std::string::npos) {
        CHECK(fs::exists(log));
        fs::remove(log);
      }
      CHECK(fs::is_empty(disk.dir));
    }
  }
}

TEST_CASE("a sweep that fills the disk keeps its finished maps, cut to the last whole one, and resumes them to an "
          "uninterrupted run's results", "[disk]") {
  // Old binary: exit 2 and the partial log deleted with every map it held (docs/io.md, "Outputs and --force").
  const fs::path dir = scratch("robust_disk_sweep");
  REQUIRE(runIn(dir, "scene --scans 8 --width 64 --height 48 --out scene").exit_code == 0);
  // 45 maps of about 2 kB each: the log and the results fit the 256 KiB disk together, but not beside the filler.
  const std::string sweep = "sweep --dataset scene --grid knn-opt --shard 0/10 --threads 1 --quiet --out ";
  REQUIRE(runIn(dir, sweep + "reference.json").exit_code == 0);
  SmallDisk disk(dir / "disk");
  if (!disk.mounted) {
    WARN("mount -t tmpfs is not permitted here (not root?): full-disk test skipped");
    return;
  }
  // A log that fills the disk, and one that fits but leaves no room for the results.
  for (const std::size_t free_bytes : {std::size_t(40) << 10, std::size_t(120) << 10}) {
    INFO(free_bytes << " bytes free");
    disk.fill(free_bytes);
    const CommandResult full = runIn(dir, sweep + "disk/r.json");
    INFO(full.output);
    CHECK(full.exit_code == 2);
    CHECK(full.output.find(": no space left on device; the ") != std::string::npos);
    CHECK(full.output.find("maps finished are kept in disk/r.json.partial.jsonl: free space, then the same command "
                           "resumes from them") != std::string::npos);
    const std::string log = fileBytes(disk.dir / "r.json.partial.jsonl");
    REQUIRE(!log.empty());
    CHECK(log.back() == '\n');  // cut back to its last whole map
    const std::size_t lines = std::size_t(std::count(log.begin(), log.end(), '\n'));
    CHECK(lines >= 2);  // the header and at least one finished map
    CHECK(full.output.find("the " + std::to_string(lines - 1) + " maps finished") != std::string::npos);
    fs::remove(disk.dir / "filler");
    const CommandResult resumed = runIn(dir, sweep + "disk/r.json");
    INFO(resumed.output);
    CHECK(resumed.exit_code == 0);
    const CommandResult same = runIn(dir, "results diff reference.json disk/r.json");
    INFO(same.output);
    CHECK(same.exit_code == 0);
    fs::remove(disk.dir / "r.json");
    CHECK(fs::is_empty(disk.dir));
  }
}

TEST_CASE("a sweep into a store that fills the disk keeps every map the disk takes, says how many, and resumes them",
          "[disk]") {
  // Old binary: the whole batch that did not fit (here every map) was rolled back, the partial store removed, and
  // the error said "database or disk is full" alone.
  const fs::path dir = scratch("robust_disk_store");
  REQUIRE(runIn(dir, "scene --scans 8 --width 64 --height 48 --out scene").exit_code == 0);
  // 450 maps, a store of about 200 kB: the first part fits the free space, the rest does not.
  const std::string sweep = "sweep --dataset scene --grid knn-opt --threads 2 --quiet --out ";
  REQUIRE(runIn(dir, sweep + "reference.db").exit_code == 0);
  SmallDisk disk(dir / "disk");
  if (!disk.mounted) {
    WARN("mount -t tmpfs is not permitted here (not root?): full-disk test skipped");
    return;
  }
  disk.fill(std::size_t(96) << 10);
  const CommandResult full = runIn(dir, sweep + "disk/r.db");
  INFO(full.output);
  CHECK(full.exit_code == 2);
  const std::size_t at = full.output.find("; the ");
  REQUIRE(at != std::string::npos);
  CHECK(full.output.find("maps finished are kept in disk/r.db.partial: free space, then the same command resumes "
                         "from them") != std::string::npos);
  CHECK(full.output.find(".tmp-") == std::string::npos);  // the names the user knows
  // The count in the message is the store's own, read by SQLite apart from occsweep.
  const CommandResult counted = runShell("python3 -c \"import sqlite3; print(sqlite3.connect('file:" +
                                         (disk.dir / "r.db.partial").string() + "?mode=ro', uri=True)"
                                         ".execute('SELECT COUNT(*) FROM maps').fetchone()[0])\"");
  INFO(counted.output);
  const std::size_t kept = std::stoul(full.output.substr(at + 6));
  CHECK(kept > 0);
  CHECK(kept < 450);
  CHECK(counted.output == std::to_string(kept) + "\n");
  fs::remove(disk.dir / "filler");
  const CommandResult resumed = runIn(dir, sweep + "disk/r.db");
  INFO(resumed.output);
  CHECK(resumed.exit_code == 0);
  const CommandResult same = runIn(dir, "results diff reference.db disk/r.db");
  INFO(same.output);
  CHECK(same.exit_code == 0);
}
