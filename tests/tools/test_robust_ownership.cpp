// Ownership by the rule of reserved names (docs/io.md, "Ownership"): entries named like occsweep's temporaries
// survive every writing command; an output created or changed while a command runs is never replaced; --force
// replaces only what carries occsweep's mark; a figure script never outlives `plot`.
#include <catch2/catch.hpp>

#include <algorithm>
#include <csignal>
#include <fcntl.h>
#include <functional>
#include <set>
#include <sys/stat.h>
#include <sys/wait.h>
#include <thread>
#include <tuple>

#include <nlohmann/json.hpp>

#include "occsweep/io/child_process.hpp"
#include "occsweep/io/output_file.hpp"
#include "occsweep/io/ownership.hpp"
#include "occsweep/sweeps/results_store.hpp"
#include "exchange_fault.hpp"
#include "robust_outputs_helpers.hpp"
#include "test_paths.hpp"

using namespace occsweep;
using namespace occsweep::test;
namespace fs = std::filesystem;

namespace {

const char* kPython = "/usr/bin/python3";

// The inputs every writing command below reads: a tiny scene, a tiny grid, two results files, a cloud.
fs::path inputs(const std::string& name) {
  const fs::path dir = processScratch(name);
  REQUIRE(runIn(dir, std::string(kTinyScene) + " --out scene").exit_code == 0);
  writeTinyGrid(dir / "tiny.json");
  REQUIRE(runIn(dir, "sweep --dataset scene --grid tiny.json --quiet --out oct.json").exit_code == 0);
  REQUIRE(runIn(dir, "sweep --dataset scene --grid knn-opt --quiet --out knn.json").exit_code == 0);
  std::ofstream cloud(dir / "a.xyz");
  for (int i = 0; i < 50; ++i) cloud << 1 + 0.01 * i << ' ' << 0.5 << ' ' << 0.02 * i << '\n';
  std::ofstream(dir / "truth.json") << R"([{"min": [0, 0, 0], "max": [1, 1, 1]}])";
  // One pose of slambook's joinMap (its first line), for its first depth image; a ci data set to rank and reproduce.
  std::ifstream poses(occsweep::test::sourceTree() / "tests/data/real/slambook_joinMap/pose.txt");
  std::string first;
  std::getline(poses, first);
  std::ofstream(dir / "pose1.txt") << first << '\n';
  REQUIRE(runIn(dir, "dataset generate --name building-plain-I --scale ci --no-preview --quiet --out gen").exit_code == 0);
  return dir;
}

// A PID no process has: a child that has exited and been reaped.
long deadPid() {
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  ::waitpid(child, nullptr, 0);
  return child;
}

std::string hexToken(SplitMix64& rng) {
  std::string t;
  while (t.size() < 32) t += "0123456789abcdef"[rng.next() % 16];
  return t;
}

// Every writing command, as (arguments with OUT for the output's name, output name, outputs it writes); reproduce
// runs its quickest step on a data set generated once.
struct Writer {
  std::string args, target;
  std::vector<std::string> outputs;
};

std::vector<Writer> writers(const fs::path& in) {
  const std::string s = shellQuoted(in) + "/";
  const std::string real = shellQuoted(occsweep::test::sourceTree() / "tests/data/real") + "/";
  return {
      {"scene --scans 2 --width 8 --height 6 --out OUT", "w", {"w"}},
      {"import cloud " + s + "a.xyz --out OUT", "w", {"w"}},
      {"map --dataset " + s + "scene --method octomap --out OUT", "m.ot", {"m.ot", "m.ot.json"}},
      {"sweep --dataset " + s + "scene --grid " + s + "tiny.json --quiet --out OUT", "r.json", {"r.json"}},
      {"merge " + s + "oct.json --out OUT", "r.json", {"r.json"}},
      {"merge " + s + "oct.json --out OUT", "r.db", {"r.db"}},
      {"compare " + s + "oct.json " + s + "knn.json --json OUT", "c.json", {"c.json"}},
      {"compare " + s + "oct.json " + s + "knn.json --csv OUT", "c.csv", {"c.csv"}},
      {"compare " + s + "oct.json " + s + "knn.json --markdown OUT", "c.md", {"c.md"}},
      {"compare " + s + "oct.json " + s + "knn.json --latex OUT", "c.tex", {"c.tex"}},
      {"results export " + s + "oct.json --out OUT", "e.csv", {"e.csv"}},
      {"results export " + s + "oct.json --out OUT", "e.db", {"e.db"}},
      {"plot improvement " + s + "oct.json " + s + "knn.json --python " + kPython + " --out OUT", "f.png", {"f.png"}},
      {"sweep --dataset " + s + "scene --grid " + s + "tiny.json --quiet --out OUT", "r.db", {"r.db"}},
      {"import truth " + s + "truth.json --dataset " + s + "scene --out OUT", "w", {"w"}},
      {"results export " + s + "oct.json --out OUT", "e.json", {"e.json"}},
      {"plot improvement " + s + "oct.json " + s + "knn.json --python " + kPython + " --out f.png --json OUT",
       "d.json", {"d.json", "f.png"}},
      {"cluster plan --experiment sweep --dataset " + s + "scene --grid " + s + "tiny.json:1 --out OUT", "p", {"p"}},
      {"import graph " + real + "octomap_share_data/spherical_scan.graph --out OUT", "w", {"w"}},
      {"import depth " + real + "slambook_joinMap/depth/1.pgm --poses " + s + "pose1.txt --fx 518 --fy 519 "
       "--cx 325.5 --cy 253.5 --stride 16 --out OUT", "w", {"w"}},
      {"dataset generate --name building-plain-I --scale ci --pcs 0 --no-preview --quiet --out OUT", "g", {"g"}},
      {"cluster select " + s + "gen/building-plain-I/ranking.json --out OUT", "sets", {"sets"}},
      {"reproduce --scale ci --name building-plain-I --steps fits --no-figures --quiet --data-root " + s + "gen --out OUT",
       "rep", {"rep"}},
  };
}

std::string withTarget(std::string args, const std::string& target) {
  return args.replace(args.find("OUT"), 3, target);
}

// A name of every pattern occsweep's temporaries ever had, for output `n`, with a PID that is dead, alive, this
// process's or impossible, and a random token; the names of SQLite's journals beside them; a sweep's
// partial results; and the figure's data file.
constexpr std::uint64_t kLookalikePatterns = 13;
std::string temporaryLookalike(const std::string& n, std::uint64_t pattern, SplitMix64& rng) {
  const long pids[] = {deadPid(), 1, long(::getpid()), 999999999};
  const std::string pid = std::to_string(pids[rng.next() % 4]);
  switch (pattern % kLookalikePatterns) {
    case 0: return "." + n + ".tmp-" + pid;
    case 1: return "." + n + ".tmp-" + pid + "-" + hexToken(rng);
    case 2: return n + ".tmp-" + pid;
    case 3: return n + ".old-" + pid;
    case 4: return n + ".tmp-" + pid + ".png";
    case 5: return "." + n + ".tmp-" + pid + "-" + hexToken(rng) + "-journal";  // SQLite's, beside a temporary
    case 6: return n + "-journal";
    case 7: return n + "-wal";
    case 8: return n + "-shm";
    case 9: return n + ".partial";        // a store sweep's partial results
    case 10: return n + ".partial.jsonl";  // a JSON sweep's
    case 11: return "." + n + ".data.json.tmp-" + pid + "-" + hexToken(rng);  // plot's data for its script
    default: return n + ".old-" + std::to_string(2000 + rng.next() % 30);
  }
}

// The look-alikes a writer must refuse to write beside, exit 2 naming one (docs/io.md, "Ownership"): a
// user's entry at a store's journal names would be taken by SQLite for the new store's transaction, and one at a
// sweep's partial results name for its resume file. Any other look-alike is simply left alone.
std::set<std::string> refusedLookalikes(const Writer& w, const std::set<std::string>& names) {
  std::set<std::string> refused;
  const bool store = fs::path(w.target).extension() == ".db", sweep = w.args.rfind("sweep ", 0) == 0;
  for (const std::string& name : names) {
    if (store && (name == w.target + "-journal" || name == w.target + "-wal" || name == w.target + "-shm"))
      refused.insert(name);
    if (sweep && name == w.target + (store ? ".partial" : ".partial.jsonl")) refused.insert(name);
  }
  return refused;
}

// A user's file or folder (with a file inside) at `path`.
void userEntry(const fs::path& path, SplitMix64& rng) {
  const std::string bytes = "a user's backup " + std::to_string(rng.next()) + "\n";
  if (rng.next() % 2 == 0) {
    writeBytes(path, bytes);
  } else {
    fs::create_directories(path / "sub");
    writeBytes(path / "sub" / "notes.txt", bytes);
  }
}

std::set<std::string> entriesOf(const fs::path& dir) {
  std::set<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.insert(e.path().filename().string());
  return names;
}

bool mentions(const CommandResult& r, const std::string& what) { return r.output.find(what) != std::string::npos; }

// A process that runs: /proc/PID exists and is not a zombie (which no one may have reaped yet).
bool running(long pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  const std::string stat((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::size_t comm_end = stat.rfind(')');
  return comm_end != std::string::npos && comm_end + 2 < stat.size() && stat[comm_end + 2] != 'Z';
}

}  // namespace

TEST_CASE("entries named like temporaries that no live occsweep made survive every writing command",
          "[ownership]") {
  // A backup named like the `.old-N` temporaries of older versions, and a folder tree (docs/robustness.md).
  const fs::path in = inputs("ownership/inputs");
  const fs::path dir = scratch("ownership/names");
  writeBytes(dir / "r.json.old-2023", "backup\n");
  fs::create_directories(dir / "data.old-2022/sub");
  writeBytes(dir / "data.old-2022/sub/x", "mine\n");
  REQUIRE(runIn(dir, "merge " + shellQuoted(in / "oct.json") + " --out r.json").exit_code == 0);
  REQUIRE(runIn(dir, "scene --scans 2 --width 8 --height 6 --out data").exit_code == 0);
  CHECK(fileBytes(dir / "r.json.old-2023") == "backup\n");
  CHECK(fileBytes(dir / "data.old-2022/sub/x") == "mine\n");

  // Then every writing command beside every pattern, once each (23 x 13 seeded cases): that pattern's look-alike of
  // one of its outputs' names, and up to 3 more of any pattern and output, files or folders.
  const std::vector<Writer> all = writers(in);
  std::uint64_t seed = 0;
  for (const Writer& w : all)
    for (std::uint64_t pattern = 0; pattern < kLookalikePatterns; ++pattern) {
      SplitMix64 rng(++seed);
      const fs::path folder = scratch("ownership/case");
      std::set<std::string> mine;
      for (std::uint64_t i = 0, n = 1 + rng.next() % 4; i < n; ++i) {
        const std::string& output = w.outputs[rng.next() % w.outputs.size()];
        const std::string name = temporaryLookalike(output, i == 0 ? pattern : rng.next(), rng);
        if (mine.insert(name).second) userEntry(folder / name, rng);
      }
      const auto before = snapshot(folder);
      const CommandResult r = runIn(folder, withTarget(w.args, w.target));
      INFO("seed " << seed << ": " << withTarget(w.args, w.target) << "\n" << r.output);
      const std::set<std::string> refused = refusedLookalikes(w, mine);
      if (!refused.empty()) {
        CHECK(r.exit_code == 2);
        CHECK(std::any_of(refused.begin(), refused.end(), [&](const std::string& n) { return mentions(r, n + ": "); }));
      } else {
        REQUIRE(r.exit_code == 0);
      }
      auto after = snapshot(folder);
      std::erase_if(after, [&](const auto& kv) { return !mine.contains(fs::path(kv.first).begin()->string()); });
      CHECK(after == before);  // every user entry, and what it holds, byte-identical
      std::set<std::string> expected = mine;
      if (refused.empty()) expected.insert(w.outputs.begin(), w.outputs.end());
      CHECK(entriesOf(folder) == expected);  // and nothing else left
    }
  CHECK(seed == 23 * kLookalikePatterns);  // every writer beside every pattern: 299 seeded cases
  CHECK(all.size() == 23);
}

/// A real `scene` run in `dir`, its output into `log`, and its temporary folder once that holds its first files
/// (empty if it never did).
struct SceneUnderWay {
  pid_t pid = -1;
  fs::path temporary;
};

SceneUnderWay sceneUnderWay(const fs::path& dir, const std::string& env, const std::string& log) {
  const std::string slow = "scene --scans 200 --width 320 --height 240 --out w";  // 15 M rays, seconds
  SceneUnderWay run;
  run.pid = startShell("cd " + shellQuoted(dir) + " && " + env + " exec " + shellQuoted(cliUnderTest()) + " " + slow +
                       " > " + log + " 2>&1");
  for (int i = 0; i < 3000 && run.temporary.empty(); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    for (const auto& e : fs::directory_iterator(dir))
      if (e.path().filename().string().starts_with(".w.tmp-") && fs::exists(e.path() / "scans") &&
          !entriesOf(e.path() / "scans").empty())
        run.temporary = e.path();
  }
  return run;
}

/// A real `scene` run SIGKILLed once its temporary folder holds its first files, in `dir`: that folder.
fs::path killedSceneFolder(const fs::path& dir, const std::string& env) {
  const SceneUnderWay run = sceneUnderWay(dir, env, "/dev/null");
  ::kill(run.pid, SIGKILL);
  ::waitpid(run.pid, nullptr, 0);
  return run.temporary;
}

TEST_CASE("an interrupted run removes its temporary only while it is the entry the run made there", "[ownership]") {
  // Old binary: the interrupt's cleaner removed whatever stood at the temporary's name, with all it held: here a
  // folder of the user's put there while the run went on (as one stands there for the moment an exchange is undone).
  const fs::path dir = scratch("ownership/interrupt_other_entry");
  const auto [pid, temporary] = sceneUnderWay(dir, "", "log");
  ::kill(pid, SIGSTOP);
  if (temporary.empty()) {
    ::kill(pid, SIGKILL);
    ::waitpid(pid, nullptr, 0);
  }
  REQUIRE(!temporary.empty());
  fs::rename(temporary, dir / "moved");
  fs::create_directories(temporary);
  writeBytes(temporary / "mine.txt", "the user's\n");
  ::kill(pid, SIGTERM);
  ::kill(pid, SIGCONT);
  int status = 0;
  ::waitpid(pid, &status, 0);
  INFO(fileBytes(dir / "log"));
  CHECK(fileBytes(temporary / "mine.txt") == "the user's\n");
}

TEST_CASE("a killed run's temporary is named by the next run writing that target, with the command that removes it, "
          "and stays whole", "[ownership]") {
  // docs/io.md, "Ownership": occsweep cannot tell what a killed run left from an entry a user made at that
  // name (no state outside the outputs' folders), so it removes neither: it names the leftover and the command.
  for (const std::string folder : {"plain", "a\nb"}) {  // a folder of any name
    INFO("folder " << folder);
    const fs::path dir = scratch("ownership/killed_temporary") / folder;
    fs::create_directories(dir);
    const fs::path left = killedSceneFolder(dir, "");
    REQUIRE(!left.empty());
    writeBytes(left.string() + "-journal", "a journal beside it\n");
    writeBytes(left / "notes.txt", "the user's notes, moved in\n");
    // A temporary's name with a live process's PID (this test's) is another run's, still writing: never named.
    const fs::path live = dir / (".w.tmp-" + std::to_string(::getpid()) + "-0123456789abcdef0123456789abcdef");
    fs::create_directories(live);
    const auto before = snapshot(dir);
    const CommandResult r = runIn(dir, std::string(kTinyScene) + " --out w");
    INFO(r.output);
    REQUIRE(r.exit_code == 0);
    const std::string shown = (fs::path(".") / left.filename()).string();
    CHECK(mentions(r, "rm -r -- " + shellWord(shown) + " " + shellWord(shown + "-journal")));  // and its journal
    CHECK(mentions(r, "whose process does not run on this machine"));
    CHECK(mentions(r, "occsweep never removes it. Once it is not in use, remove it:"));
    CHECK_FALSE(mentions(r, live.filename().string()));
    auto after = snapshot(dir);
    std::erase_if(after, [](const auto& kv) { return fs::path(kv.first).begin()->string() == "w"; });
    CHECK(after == before);  // the leftover, its journal, the user's file in it and the live one: byte-identical
  }
}

TEST_CASE("occsweep keeps no state outside its outputs' folders: a state folder of a user's files and FIFOs is never "
          "read, changed or blocked on", "[ownership]") {
  // Old binary (its ledger under OCCSWEEP_STATE_DIR, else XDG_STATE_HOME, else HOME): `compare --csv` deleted the
  // user's outputs/notes.txt there and every hour-old file in temporaries/, a sweep deleted old files in made/, and
  // a FIFO in those folders hung merge, compare --csv and sweep.
  const fs::path in = inputs("ownership/state_inputs");
  const fs::path dir = scratch("ownership/state");
  const fs::path state = dir / "state";
  const std::vector<std::string> folders = {"outputs", "temporaries", "made", "occsweep/outputs",
                                            "occsweep/temporaries", "occsweep/made", ".local/state/occsweep/outputs",
                                            ".local/state/occsweep/made", ".local/state/occsweep/temporaries"};
  for (const std::string& folder : folders) {
    fs::create_directories(state / folder);
    writeBytes(state / folder / "notes.txt", "the user's notes\n");
    writeBytes(state / folder / "old.txt", "an old file of the user's\n");
    fs::last_write_time(state / folder / "old.txt", fs::file_time_type::clock::now() - std::chrono::hours(2));
  }
  const std::string env = "OCCSWEEP_STATE_DIR=" + shellQuoted(state) + " XDG_STATE_HOME=" + shellQuoted(state) +
                          " HOME=" + shellQuoted(state);
  const std::string s = shellQuoted(in) + "/";
  const std::vector<std::string> commands = {"compare " + s + "oct.json " + s + "knn.json --csv t.csv --force",
                                             "merge " + s + "oct.json --out m.json --force",
                                             "sweep --dataset " + s + "scene --grid " + s + "tiny.json --quiet "
                                             "--out r.json --force",
                                             std::string(kTinyScene) + " --out w --force"};
  // The user's files alone (D10), then a FIFO beside each (H3).
  for (const bool fifos : {false, true}) {
    INFO((fifos ? "with FIFOs" : "files only"));
    if (fifos)
      for (const std::string& folder : folders) REQUIRE(::mkfifo((state / folder / "pipe").c_str(), 0600) == 0);
    const auto before = snapshot(state);
    for (const std::string& command : commands) {
      const CommandResult r = runShell("cd " + shellQuoted(dir) + " && " + env + " timeout 60 " +
                                       shellQuoted(cliUnderTest()) + " " + command + " 2>&1");
      INFO(command << "\n" << r.output);
      CHECK(r.exit_code == 0);  // 124: it blocked on a FIFO
    }
    CHECK(snapshot(state) == before);
  }
}

TEST_CASE("a table occsweep wrote is its own to replace through any spelling of its path, and a file that is not a "
          "table of its kind never is", "[ownership]") {
  const fs::path in = inputs("ownership/tables-identity");
  const std::string s = shellQuoted(in) + "/";
  const fs::path dir = scratch("ownership/tables-identity-out");
  fs::create_directories(dir / "real");
  fs::create_directory_symlink("real", dir / "link");
  const std::string compare = "compare " + s + "oct.json " + s + "knn.json --force --csv ";
  REQUIRE(runIn(dir, compare + "link/t.csv").exit_code == 0);
  // Written through the link, replaced through the folder (old binary: refused, the record named the other spelling).
  const CommandResult r = runIn(dir, compare + "real/t.csv");
  INFO(r.output);
  CHECK(r.exit_code == 0);
  CHECK(runIn(dir, compare + "./link/../real/t.csv").exit_code == 0);
  // A file of the user's at the name: another first line, a second name (a hard link), a link: refused, unchanged.
  writeBytes(dir / "notes.csv", "name,value\nmine,1\n");
  fs::copy_file(dir / "real/t.csv", dir / "linked.csv");
  fs::create_hard_link(dir / "linked.csv", dir / "linked-backup.csv");
  fs::create_symlink("real/t.csv", dir / "symlink.csv");
  for (const std::string name : {"notes.csv", "linked.csv", "symlink.csv"}) {
    const auto before = snapshot(dir);
    const CommandResult refused = runIn(dir, compare + name);
    INFO(name << "\n" << refused.output);
    CHECK(refused.exit_code == 2);
    CHECK(mentions(refused, name + ": "));
    CHECK(snapshot(dir) == before);
  }
}

TEST_CASE("an output whose '..' follows a symbolic link is refused before anything is read or written",
          "[ownership]") {
  // Old binary: `sweep --out deep/l5/../l5/o.json`, deep/l5 a link to k5, checked the system's reading (l5/o.json
  // beside k5, absent) and wrote the lexical one (k5/o.json): a user's results of another grid replaced, exit 0.
  const fs::path in = inputs("ownership/dotdot");
  const fs::path dir = scratch("ownership/dotdot-out");
  fs::create_directories(dir / "k5");
  fs::create_directories(dir / "deep");
  fs::copy_file(in / "oct.json", dir / "k5/o.json");
  fs::create_directory_symlink("../k5", dir / "deep/l5");
  const auto before = snapshot(dir);
  const std::vector<std::string> commands = {"sweep --dataset " + shellQuoted(in / "scene") + " --grid knn-opt --quiet",
                                             "merge " + shellQuoted(in / "knn.json"), "scene --scans 2 --width 8 --height 6"};
  for (const std::string& command : commands) {
    const CommandResult r = runIn(dir, command + " --out deep/l5/../l5/o.json");
    INFO(command << "\n" << r.output);
    CHECK(r.exit_code == 2);
    CHECK(mentions(r, "deep/l5/../l5/o.json: '..' after a symbolic link names"));
    CHECK(snapshot(dir) == before);
  }
}

namespace {

// A child process that makes and drops temporaries of every kind on two threads, in a loop (a results store at an
// OutputFile's temporary, as `results export` writes one, an OutputFolder, a store at a RegisteredTemporary file, as a
// sweep's partial store is made, a RegisteredTemporary folder), and sends itself SIGINT after `delay_us`. Returns its exit code (130 when the interrupt's cleaner ended it).
int interruptedWhileMaking(const fs::path& dir, const ResultsHeader& header, unsigned delay_us) {
  const pid_t child = ::fork();
  if (child == 0) {
    removeTemporariesOnInterrupt();
    for (int maker = 0; maker < 2; ++maker)
      std::thread([dir, header] {
        for (;;) {
          try {
            OutputFile file(dir / "f.db");
            (void)ResultsStore::create(file.temporary(), header, StoreUse::Temporary);
            const OutputFolder folder(dir / "d");
            const RegisteredTemporary store(dir / "s.db", TemporaryKind::File);
            (void)ResultsStore::create(store.path(), header, StoreUse::Temporary);
            const RegisteredTemporary figures(dir / "figures", TemporaryKind::Folder);
            std::ofstream(figures.path() / "a.png") << "drawn";
          } catch (const std::exception&) {
          }
        }
      }).detach();
    ::usleep(delay_us);
    ::kill(::getpid(), SIGINT);
    for (;;) ::pause();  // the cleaner's _exit ends the process
  }
  int status = 0;
  ::waitpid(child, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace

TEST_CASE("an interrupt while temporaries are being made leaves none behind, at 150 seeded moments", "[ownership]") {
  // Old library: a temporary was registered, then made once the registry's lock was released, and SQLite created a
  // store's temporary itself. An interrupt's cleaner that ran in between removed nothing, or removed the file SQLite
  // then made again, before the exit: `.s.db.tmp-PID-TOKEN` (or another) was left beside the target for good.
  const fs::path dir = scratch("ownership/interrupted-makers");
  REQUIRE(runIn(dir, std::string(kTinyScene) + " --out scene").exit_code == 0);
  writeTinyGrid(dir / "tiny.json");
  REQUIRE(runIn(dir, "sweep --dataset scene --grid tiny.json --quiet --out oct.json").exit_code == 0);
  const ResultsHeader header = readResultsHeader(dir / "oct.json").header;
  SplitMix64 rng(31);
  for (int moment = 0; moment < 150; ++moment) {
    const fs::path out = dir / ("run" + std::to_string(moment));
    fs::create_directories(out);
    const unsigned delay_us = unsigned(rng.next() % 4000);
    INFO("delay " << delay_us << " us");
    CHECK(interruptedWhileMaking(out, header, delay_us) == 130);
    CHECK(entriesOf(out).empty());
  }
}

TEST_CASE("an output created or changed while occsweep writes it is kept, and the commit fails naming it",
          "[ownership]") {
  const fs::path dir = scratch("ownership/meanwhile");
  const ReplaceableOutput kind{"text", [](const fs::path&) { return true; }};
  SECTION("a file created after the check") {
    checkOutputTarget(dir / "a.txt", false, kind);
    writeBytes(dir / "a.txt", "the user's\n");
    CHECK_THROWS_WITH(writeFileAtomically(dir / "a.txt", "occsweep's\n"),
                      Catch::Contains("a.txt: was created while occsweep was writing it: nothing was replaced"));
    CHECK(fileBytes(dir / "a.txt") == "the user's\n");
  }
  SECTION("a folder created after the check") {
    checkOutputTarget(dir / "w", false, kind);
    fs::create_directories(dir / "w");
    writeBytes(dir / "w" / "thesis.tex", "mine\n");
    OutputFolder folder(dir / "w");
    writeFileChecked(folder.path() / "manifest.json", "{}\n");
    CHECK_THROWS_WITH(folder.commit(), Catch::Contains("w: was created while occsweep was writing it"));
    CHECK(fileBytes(dir / "w" / "thesis.tex") == "mine\n");
  }
  SECTION("an own output accepted by --force, replaced by the user's file meanwhile") {
    writeBytes(dir / "b.txt", "occsweep's old\n");
    checkOutputTarget(dir / "b.txt", true, kind);
    fs::remove(dir / "b.txt");
    writeBytes(dir / "b.txt", "the user's new\n");
    CHECK_THROWS_WITH(writeFileAtomically(dir / "b.txt", "occsweep's\n"), Catch::Contains("b.txt: was changed"));
    CHECK(fileBytes(dir / "b.txt") == "the user's new\n");
  }
  SECTION("a file put at a target no check accepted, before the write began: kept") {
    // Old code: a target no checkOutputTarget accepted was taken as it stood when the write began, so reproduce's
    // report.md and step files replaced a user's file put there while the run went on.
    writeBytes(dir / "report.md", "the user's report\n");
    CHECK_THROWS_WITH(writeFileAtomically(dir / "report.md", "occsweep's\n"),
                      Catch::Contains("report.md: was created while occsweep was writing it"));
    CHECK(fileBytes(dir / "report.md") == "the user's report\n");
    fs::remove(dir / "report.md");
  }
  SECTION("outputs committed together: one taken meanwhile, none committed") {
    // Old binary: map's .ot.json, compare's first tables and plot's --json were committed before the output whose
    // name had been taken, and stayed.
    checkOutputTarget(dir / "d.ot", false, kind);
    checkOutputTarget(dir / "d.ot.json", false, kind);
    OutputFile map(dir / "d.ot"), settings(dir / "d.ot.json");
    map.stream() << "map";
    settings.stream() << "settings";
    writeBytes(dir / "d.ot", "the user's map\n");
    CHECK_THROWS_WITH(OutputFile::commitTogether({&settings, &map}), Catch::Contains("d.ot: was created"));
    CHECK(fileBytes(dir / "d.ot") == "the user's map\n");
    CHECK_FALSE(fs::exists(dir / "d.ot.json"));
    fs::remove(dir / "d.ot");
  }
  SECTION("an own folder whose content the user changed meanwhile is exchanged back, or kept where that fails") {
    // Old code: the exchange back's failure was ignored, and the user's folder, left at the temporary's name, was
    // removed with it.
    if (!test::exchangeSupported(dir)) {
      WARN("no RENAME_EXCHANGE on this file system: an own folder is removed, then renamed, never exchanged");
      return;
    }
    const ReplaceableOutput own_folder{"folder", [](const fs::path& d) { return fileBytes(d / "x") == "old\n"; }};
    fs::create_directories(dir / "f");
    for (const bool exchange_back_fails : {false, true}) {
      INFO("exchange back fails: " << exchange_back_fails);
      writeBytes(dir / "f" / "x", "old\n");
      checkOutputTarget(dir / "f", true, own_folder);
      OutputFolder folder(dir / "f");
      writeFileChecked(folder.path() / "x", "new\n");
      writeBytes(dir / "f" / "x", "the user's\n");  // in place: the folder itself is the entry that was checked
      const test::ExchangeFault fault(exchange_back_fails ? 1 : -1, false);
      if (!exchange_back_fails) {
        CHECK_THROWS_WITH(folder.commit(), Catch::Contains("f: was changed while occsweep was writing it"));
        CHECK(fileBytes(dir / "f" / "x") == "the user's\n");
        continue;
      }
      CHECK_THROWS_WITH(folder.commit(),
                        Catch::Contains("f: was changed while occsweep was writing it, and could not be put back "
                                        "(Input/output error): what stood there is now at " + folder.path().string() +
                                        ", occsweep's new output at " + (dir / "f").string()));
      CHECK(fileBytes(folder.path() / "x") == "the user's\n");
      CHECK(fileBytes(dir / "f" / "x") == "new\n");
    }
    // The folder the user's content is in survives this run too (the OutputFolder is gone by now).
    std::vector<fs::path> kept;
    for (const auto& e : fs::directory_iterator(dir))
      if (e.path().filename().string().starts_with(".f.tmp-")) kept.push_back(e.path());
    REQUIRE(kept.size() == 1);
    CHECK(fileBytes(kept[0] / "x") == "the user's\n");
    fs::remove_all(kept[0]);
    fs::remove_all(dir / "f");
  }
  SECTION("a user's file put at the temporary's name meanwhile is never committed as the output") {
    // Old code: the commit renamed whatever stood at the temporary's name, so the user's file became the output.
    OutputFile out(dir / "t.txt");
    out.stream() << "occsweep's\n";
    fs::path temporary;
    for (const auto& e : fs::directory_iterator(dir))
      if (e.path().filename().string().starts_with(".t.txt.tmp-")) temporary = e.path();
    REQUIRE(!temporary.empty());
    fs::rename(temporary, dir / "moved");
    writeBytes(temporary, "the user's\n");
    CHECK_THROWS_WITH(out.commit(), Catch::Contains("was replaced or removed while occsweep was writing it"));
    CHECK_FALSE(fs::exists(dir / "t.txt"));
    CHECK(fileBytes(temporary) == "the user's\n");
    fs::remove(temporary);
    fs::remove(dir / "moved");
  }
  SECTION("guards: an absent target stays writable, an accepted own output is replaced, a second commit too") {
    checkOutputTarget(dir / "c.txt", false, kind);
    writeFileAtomically(dir / "c.txt", "1\n");
    writeFileAtomically(dir / "c.txt", "2\n");  // the command's own first write is no one else's
    CHECK(fileBytes(dir / "c.txt") == "2\n");
  }
  CHECK(leftovers(dir).empty());
}

TEST_CASE("plot keeps an output created while its script draws, exit 2", "[ownership]") {
  const fs::path in = inputs("ownership/plot_inputs");
  const fs::path dir = scratch("ownership/plot_meanwhile");
  // A Python that creates the figure's name before it draws: as another program would while plot runs.
  std::ofstream(dir / "py.sh") << "#!/bin/sh\n[ -e fig.png ] || echo user > fig.png\nexec " << kPython
                               << " \"$@\"\n";
  fs::permissions(dir / "py.sh", fs::perms::owner_all);
  const CommandResult r = runIn(dir, "plot improvement " + shellQuoted(in / "oct.json") + " " +
                                         shellQuoted(in / "knn.json") + " --python ./py.sh --out fig.png --json d.json");
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK(mentions(r, "fig.png: was created while occsweep was writing it"));  // and d.json not committed either
  CHECK(fileBytes(dir / "fig.png") == "user\n");
  CHECK(entriesOf(dir) == std::set<std::string>{"fig.png", "py.sh"});
}

TEST_CASE("plot whose script exits 0 without drawing writes nothing, exit 2", "[ownership]") {
  // Old binary: exit 0 and an empty fig.png, which a later --force then refused as not occsweep's figure.
  const fs::path in = inputs("ownership/plot_empty_inputs");
  const fs::path dir = scratch("ownership/plot_empty");
  std::ofstream(dir / "py.sh") << "#!/bin/sh\nexit 0\n";  // passes the matplotlib probe, draws nothing
  fs::permissions(dir / "py.sh", fs::perms::owner_all);
  const CommandResult r = runIn(dir, "plot improvement " + shellQuoted(in / "oct.json") + " " +
                                         shellQuoted(in / "knn.json") + " --python ./py.sh --out fig.png --json d.json");
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK(mentions(r, "exited 0 but drew no figure (nothing written)"));
  CHECK(entriesOf(dir) == std::set<std::string>{"py.sh"});
}

TEST_CASE("plot --force replaces only a PNG whose Software chunk is occsweep's", "[ownership]") {
  const fs::path in = inputs("ownership/plot_force_inputs");
  const fs::path dir = scratch("ownership/plot_force");
  const std::string files = shellQuoted(in / "oct.json") + " " + shellQuoted(in / "knn.json");
  // A user's figure that says "occsweep plot" in its description.
  REQUIRE(runShell(std::string(kPython) + " -c \"import matplotlib; matplotlib.use('Agg'); import matplotlib.pyplot "
                   "as plt; plt.figure().savefig('" + (dir / "mine.png").string() +
                   "', metadata={'Description': 'occsweep plot, redrawn by hand'})\"").exit_code == 0);
  const std::string mine = fileBytes(dir / "mine.png");
  const CommandResult refused = runIn(dir, "plot improvement " + files + " --force --out mine.png");
  INFO(refused.output);
  CHECK(refused.exit_code == 2);
  CHECK(mentions(refused, "mine.png: exists and is not occsweep's figure"));
  CHECK(fileBytes(dir / "mine.png") == mine);
  // The guard: occsweep's own figure is replaced with --force.
  REQUIRE(runIn(dir, "plot improvement " + files + " --out own.png").exit_code == 0);
  CHECK(runIn(dir, "plot curves " + files + " --force --out own.png").exit_code == 0);
  CHECK(entriesOf(dir) == std::set<std::string>{"mine.png", "own.png"});
  // occsweep's figure with the user's bytes after its end, or its last CRC cut off, is no longer a PNG occsweep
  // wrote (old binary: both replaced, since the Software chunk alone was read).
  const std::string own = fileBytes(dir / "own.png");
  writeBytes(dir / "appended.png", own + "the user's notes");
  writeBytes(dir / "cut.png", own.substr(0, own.size() - 4));
  for (const std::string name : {"appended.png", "cut.png"}) {
    const std::string before = fileBytes(dir / name);
    const CommandResult r = runIn(dir, "plot curves " + files + " --force --out " + name);
    INFO(name << "\n" << r.output);
    CHECK(r.exit_code == 2);
    CHECK(mentions(r, name + ": exists and is not occsweep's figure"));
    CHECK(fileBytes(dir / name) == before);
  }
}

TEST_CASE("scene --force refuses a data set folder holding a file its manifest does not name", "[ownership]") {
  const fs::path dir = scratch("ownership/dataset_force");
  REQUIRE(runIn(dir, std::string(kTinyScene) + " --out w").exit_code == 0);
  writeBytes(dir / "w/scans/000099.f32", "a user's scan");
  const auto before = snapshot(dir);
  const CommandResult r = runIn(dir, std::string(kTinyScene) + " --out w --force");
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK(mentions(r, "w: exists and is not occsweep's data set folder"));
  CHECK(snapshot(dir) == before);
  // The guard: without the stranger, occsweep's own data set is replaced.
  fs::remove(dir / "w/scans/000099.f32");
  CHECK(runIn(dir, std::string(kTinyScene) + " --out w --force").exit_code == 0);
}

TEST_CASE("plot killed at 20 seeded moments: its figure script ends with it and no file is left", "[ownership]") {
  // SIGINT and SIGTERM: occsweep removes its temporaries itself; SIGKILL: the next run does.
  const fs::path in = inputs("ownership/plot_kill_inputs");
  const fs::path dir = scratch("ownership/plot_kill");
  // The script's process writes its PID: `exec` keeps it, so it is the process occsweep started.
  std::ofstream(dir / "py.sh") << "#!/bin/sh\necho $$ >> pids\nexec " << kPython << " \"$@\"\n";
  fs::permissions(dir / "py.sh", fs::perms::owner_all);
  const std::string args = shellQuoted(cliUnderTest()) + " plot improvement " + shellQuoted(in / "oct.json") + " " +
                           shellQuoted(in / "knn.json") + " --python ./py.sh --out fig.png";
  // One run uninterrupted, timed: the kills are spread over its length, however fast this machine is.
  const auto start = std::chrono::steady_clock::now();
  REQUIRE(runShell("cd " + shellQuoted(dir) + " && " + args).exit_code == 0);
  const long run_ms = long(std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() -
                                                                                start).count());
  int killed_while_drawing = 0;
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    SplitMix64 rng(seed);
    fs::remove(dir / "fig.png");
    fs::remove(dir / "pids");
    const pid_t pid = startShell("cd " + shellQuoted(dir) + " && exec " + args + " >/dev/null 2>&1");
    std::this_thread::sleep_for(std::chrono::milliseconds(std::uint64_t(run_ms) * (5 + rng.next() % 90) / 100));
    // A third of the kills are SIGKILL, which occsweep cannot catch: the kernel ends the script
    // (PR_SET_PDEATHSIG), and the next run writing the figure names the temporaries the killed run left.
    const int sig = seed % 3 == 0 ? SIGKILL : seed % 2 ? SIGTERM : SIGINT;
    ::kill(pid, sig);
    int status = 0;
    ::waitpid(pid, &status, 0);
    bool finished = WIFEXITED(status) && WEXITSTATUS(status) == 0;
    INFO("seed " << seed << ", signal " << sig << ", exit " << (WIFEXITED(status) ? WEXITSTATUS(status) : -1)
                  << ", ended by signal " << (WIFSIGNALED(status) ? WTERMSIG(status) : 0));
    // A SIGINT or SIGTERM that lands before occsweep has set its handler (a slow start, as under ASan) ends it the
    // default way; it has started nothing then: no script, and the entries below hold no temporary.
    const bool ended_before_handler = WIFSIGNALED(status) && WTERMSIG(status) == sig && !fs::exists(dir / "pids");
    if (sig == SIGKILL)
      CHECK((finished || (WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL)));
    else
      CHECK((finished || ended_before_handler || (WIFEXITED(status) && WEXITSTATUS(status) == 128 + sig)));
    // No script survives: each PID it wrote is gone within 2 s (PR_SET_PDEATHSIG, or killed and reaped).
    std::ifstream pids(dir / "pids");
    for (long child; pids >> child;) {
      bool gone = false;
      for (int i = 0; i < 40 && !gone; ++i) {
        gone = !running(child);
        if (!gone) std::this_thread::sleep_for(std::chrono::milliseconds(50));
      }
      CHECK(gone);
    }
    std::ifstream last(dir / "pids");
    int started = 0;
    for (long child; last >> child;) ++started;
    if (!finished && started == 2) ++killed_while_drawing;
    std::set<std::string> expected = {"py.sh", "pids"};
    if (sig == SIGKILL && !finished) {
      // The killed run's temporaries stay, and the next run names each with the command that removes it.
      std::set<std::string> left = entriesOf(dir);
      for (const char* n : {"py.sh", "pids"}) left.erase(n);
      const CommandResult next = runShell("cd " + shellQuoted(dir) + " && " + args + " 2>&1");
      INFO(next.output);
      REQUIRE(next.exit_code == 0);
      for (const std::string& entry : left) {
        CHECK(isLeftoverTemporaryOf(dir / entry, dir / outputNameOf(entry)));
        CHECK(mentions(next, "rm -r -- " + shellWord((fs::path(".") / entry).string())));
        fs::remove_all(dir / entry);  // as the user does, following the message
      }
      finished = true;  // the next run: its figure
    }
    if (finished) expected.insert("fig.png");
    if (!finished && fs::exists(dir / "fig.png")) {  // the signal came after the figure was in place (a loaded
      // machine): it is whole, its last chunk IEND, never half a figure
      const std::string png = bytesOf(dir / "fig.png");
      CHECK(png.size() > 12);
      CHECK(png.substr(png.size() - 12) == std::string("\0\0\0\0IEND\xAE\x42\x60\x82", 12));
      expected.insert("fig.png");
    }
    if (!fs::exists(dir / "pids")) expected.erase("pids");
    CHECK(entriesOf(dir) == expected);  // no temporary, no data file, no half figure
  }
  CHECK(killed_while_drawing >= 3);  // the seeds do hit the script at work, not only before or after it
}

TEST_CASE("cluster select refuses its own folder of links once it holds a link it did not list", "[ownership]") {
  const fs::path dir = scratch("ownership/select");
  fs::create_directories(dir / "ds/pcs-0000");
  std::ofstream(dir / "ds/ranking.json") << R"({"format": "occsweep-pointcloud-ranking",
    "sets": [{"folder": "pcs-0000", "id": 0, "naive": {"fdr": 0.1, "tpr": 0.9}}]})";
  REQUIRE(runIn(dir, "cluster select ds/ranking.json --out sel").exit_code == 0);
  fs::create_directory_symlink("../ds", dir / "sel/my-link");  // the user's, inside occsweep's folder
  const auto before = snapshot(dir);
  const CommandResult r = runIn(dir, "cluster select ds/ranking.json --out sel");
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK(mentions(r, "exists and is not occsweep's folder of selected point cloud sets"));
  CHECK(snapshot(dir) == before);
  fs::remove(dir / "sel/my-link");  // the guard: its own folder alone is replaced
  CHECK(runIn(dir, "cluster select ds/ranking.json --out sel").exit_code == 0);
}

TEST_CASE("a legal 255-byte output name is written, and one without room for its companion file is refused naming "
          "the longest that fits", "[ownership]") {
  const fs::path in = inputs("ownership/long_inputs");
  const fs::path dir = scratch("ownership/long_names");
  const std::string json_name = std::string(250, 'n') + ".json", folder_name(255, 'd');
  const std::string compared = std::string(1, 'c').append(json_name, 1), swept = std::string(1, 's').append(json_name, 1);
  CHECK(runIn(dir, "merge " + shellQuoted(in / "oct.json") + " --out " + json_name).exit_code == 0);
  CHECK(runIn(dir, "compare " + shellQuoted(in / "oct.json") + " --json " + compared).exit_code == 0);
  CHECK(runIn(dir, "scene --scans 2 --width 8 --height 6 --out " + folder_name).exit_code == 0);
  CHECK(entriesOf(dir) == std::set<std::string>{json_name, compared, folder_name});
  const CommandResult sweep = runIn(dir, "sweep --dataset " + shellQuoted(in / "scene") + " --grid " +
                                             shellQuoted(in / "tiny.json") + " --quiet --out " + swept);
  INFO(sweep.output);
  CHECK(sweep.exit_code == 2);
  CHECK(mentions(sweep, "leaves no room for its companion NAME.partial.jsonl (a file name has at most 255 bytes): "
                        "choose a name of at most 241 bytes"));
  CHECK(entriesOf(dir).size() == 3);
}

namespace {

// The partial output a sweep into `out` keeps while it runs.
fs::path partialOf(const fs::path& dir, const std::string& out) {
  return dir / (out + (out == "r.db" ? ".partial" : ".partial.jsonl"));
}

// Sweeps octomap-opt (direct engine: seconds) on `dir`/big into `out`, pauses it (SIGSTOP) once it is under way (its
// partial output exists, its output not yet), runs `meanwhile`, resumes it and returns its exit code.
int sweepPausedOnceUnderWay(const fs::path& dir, const std::string& out, const std::function<void()>& meanwhile) {
  const fs::path partial = partialOf(dir, out);
  const pid_t pid = startShell("cd " + shellQuoted(dir) + " && exec " + shellQuoted(cliUnderTest()) +
                               " sweep --dataset big --grid octomap-opt --engine direct --threads 1 --quiet --out " +
                               out + " > log 2>&1");
  for (int i = 0; i < 30000 && !fs::exists(partial); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  ::kill(pid, SIGSTOP);
  const bool under_way = fs::exists(partial) && !fs::exists(dir / out);
  meanwhile();
  ::kill(pid, SIGCONT);
  int status = 0;
  ::waitpid(pid, &status, 0);
  REQUIRE(under_way);
  INFO(fileBytes(dir / "log"));
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

}  // namespace

TEST_CASE("a sweep reuses its complete output only when it passes results check, an edited one is refused, and "
          "--force sweeps it anew", "[ownership]") {
  // Old binary: the edited file was taken as the sweep's results ("wrote ...", exit 0), and reproduce printed them.
  const fs::path in = inputs("ownership/reuse_checked_inputs");
  const fs::path dir = scratch("ownership/reuse_checked");
  const std::string sweep = "sweep --dataset " + shellQuoted(in / "scene") + " --grid octomap-opt --quiet --out ";
  for (const std::string out : {"e.json", "e.db"}) {
    INFO(out);
    REQUIRE(runIn(dir, sweep + "clean-" + out).exit_code == 0);
    // One map's p_h moved off the grid: the file is still whole and of the same work, but results check refuses it.
    REQUIRE(runIn(dir, "results export clean-" + out + " --out edited.json").exit_code == 0);
    std::string text = fileBytes(dir / "edited.json");
    const std::size_t at = text.find("\"p_h\": 0.5");
    REQUIRE(at != std::string::npos);
    text.replace(at, std::string("\"p_h\": 0.5").size(), "\"p_h\": 0.51");
    writeBytes(dir / "edited.json", text);
    REQUIRE(runIn(dir, "results export edited.json --out " + out).exit_code == 2);  // export refuses it too
    if (out == "e.db") {
      // A store edited the same way, in SQLite (export would refuse to write the edited JSON into a store).
      fs::copy_file(dir / ("clean-" + out), dir / out);
      REQUIRE(runShell("cd " + shellQuoted(dir) + " && python3 -c \"import sqlite3; c = sqlite3.connect('" + out +
                       "'); c.execute('UPDATE maps SET p_h = 0.51 WHERE map_index = 0'); c.commit()\" 2>&1")
                  .exit_code == 0);
    } else {
      fs::rename(dir / "edited.json", dir / out);
    }
    REQUIRE(runIn(dir, "results check " + out).exit_code == 2);
    const std::string before = fileBytes(dir / out);
    const CommandResult r = runIn(dir, sweep + out);
    INFO(r.output);
    CHECK(r.exit_code == 2);
    CHECK(mentions(r, "(the results at --out fail `results check`); --force sweeps them anew"));
    CHECK(fileBytes(dir / out) == before);
    const CommandResult forced = runIn(dir, sweep + out + " --force");
    INFO(forced.output);
    CHECK(forced.exit_code == 0);
    CHECK(runIn(dir, "results check " + out).exit_code == 0);
    fs::remove(dir / "edited.json");
  }
}

TEST_CASE("a sweep resuming a killed run's partial store keeps a user's file at the store's journal name, exit 2",
          "[ownership]") {
  // Old binary: SQLite took the file for the store's unfinished transaction on opening it, and deleted it, exit 0.
  const fs::path dir = scratch("ownership/resume_journal");
  REQUIRE(runIn(dir, "scene --scans 16 --width 64 --height 48 --out big").exit_code == 0);
  const std::string sweep = "sweep --dataset big --grid octomap-opt --engine direct --threads 1 --quiet --out r.db";
  const fs::path partial = dir / "r.db.partial", journal = dir / "r.db.partial-journal";
  const pid_t pid = startShell("cd " + shellQuoted(dir) + " && exec " + shellQuoted(cliUnderTest()) + " " + sweep +
                               " > log 2>&1");
  for (int i = 0; i < 30000 && !fs::exists(partial); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  ::kill(pid, SIGKILL);
  int status = 0;
  ::waitpid(pid, &status, 0);
  REQUIRE(fs::exists(partial));
  REQUIRE_FALSE(fs::exists(journal));  // killed before its first batch: no transaction was open
  for (const std::string& users : {std::string("user notes\n"), std::string()}) {
    writeBytes(journal, users);
    const CommandResult r = runIn(dir, sweep);
    INFO(r.output);
    CHECK(r.exit_code == 2);
    CHECK(mentions(r, "r.db.partial-journal: is not a rollback journal SQLite wrote"));
    CHECK(fileBytes(journal) == users);
    CHECK(fs::exists(partial));
    CHECK_FALSE(fs::exists(dir / "r.db"));
  }
  fs::remove(journal);
  const CommandResult resumed = runIn(dir, sweep);
  INFO(resumed.output);
  CHECK(resumed.exit_code == 0);
  CHECK(runIn(dir, "results check r.db").exit_code == 0);
  CHECK_FALSE(fs::exists(partial));
}

TEST_CASE("a sweep keeps a file created at its --out while it runs, JSON and store, exit 2", "[ownership]") {
  const fs::path dir = scratch("ownership/sweep_meanwhile");
  REQUIRE(runIn(dir, "scene --scans 16 --width 64 --height 48 --out big").exit_code == 0);
  for (const std::string out : {"r.json", "r.db"}) {
    INFO(out);
    const int code = sweepPausedOnceUnderWay(dir, out, [&] { writeBytes(dir / out, "the user's file\n"); });
    INFO(fileBytes(dir / "log"));
    CHECK(code == 2);
    CHECK(fileBytes(dir / "log").find(out + ": was created while occsweep was writing it") != std::string::npos);
    CHECK(fileBytes(dir / out) == "the user's file\n");
    // Every map stays in the partial output (old binary: the JSON sweep's log was removed, its maps lost): once the
    // user's file is moved away, the next run resumes from it.
    CHECK(fs::exists(partialOf(dir, out)));
    fs::rename(dir / out, dir / "users");
    const CommandResult again = runIn(dir, "sweep --dataset big --grid octomap-opt --engine direct --threads 1 "
                                           "--quiet --out " + out);
    INFO(again.output);
    CHECK(again.exit_code == 0);
    CHECK_FALSE(fs::exists(partialOf(dir, out)));
    for (const std::string& name : {out, std::string("users")}) fs::remove(dir / name);
  }
}

TEST_CASE("a sweep removes its partial output only while it is the file it made, never one put at its name",
          "[ownership]") {
  const fs::path dir = scratch("ownership/partial_swapped");
  REQUIRE(runIn(dir, "scene --scans 16 --width 64 --height 48 --out big").exit_code == 0);
  for (const std::string out : {"r.json", "r.db"}) {
    INFO(out);
    const fs::path partial = partialOf(dir, out);
    const int code = sweepPausedOnceUnderWay(dir, out, [&] {
      fs::rename(partial, dir / "moved");  // the user moves it away and keeps a file of their own at its name
      writeBytes(partial, "the user's notes\n");
    });
    INFO(fileBytes(dir / "log"));
    CHECK(fileBytes(partial) == "the user's notes\n");
    if (out == "r.json") {  // the log goes on in the moved file, the results are written, the user's file stays
      CHECK(code == 0);
      CHECK(fs::exists(dir / "r.json"));
    } else {  // SQLite will not write a store moved away: the sweep stops, naming it
      CHECK(code == 2);
      const std::string log = fileBytes(dir / "log");  // said by SQLite, or by the sweep before it opens the store
      CHECK(log.find("r.db.partial: ") != std::string::npos);
      CHECK(log.find(" while occsweep was writing it") != std::string::npos);
      CHECK_FALSE(fs::exists(dir / "r.db"));
    }
    for (const char* name : {"moved", "r.json", "r.db"}) fs::remove(dir / name);
    fs::remove(partial);
  }
}

namespace {
// A sweep of knn-opt into `dir`/r.json killed once its partial log holds its header and a few maps.
void killedSweep(const fs::path& dir) {
  const std::string sweep = "sweep --dataset scene --grid knn-opt --engine direct --threads 1 --quiet --out r.json";
  REQUIRE(killOnceLogged(dir, sweep, dir / "r.json.partial.jsonl", 4).lines >= 4);
  REQUIRE_FALSE(fs::exists(dir / "r.json"));
}

// `sweep` run as it is and with --force: each exits 2 naming `refusal`, and `dir` is left byte for byte as it was.
void refusedWithAndWithoutForce(const fs::path& dir, const std::string& sweep, const std::string& refusal) {
  const auto before = snapshot(dir);
  for (const std::string force : {"", " --force"}) {
    const CommandResult r = runIn(dir, sweep + force);
    INFO(force << "\n" << r.output);
    CHECK(r.exit_code == 2);
    CHECK(mentions(r, refusal));
    CHECK(snapshot(dir) == before);
  }
}
}  // namespace

TEST_CASE("a file at a sweep's partial-log name holding a user's lines, or no sweep header, is never resumed from, "
          "replaced or removed", "[ownership]") {
  // An older binary took the first line alone as proof: the sweep resumed from it (exit 0) and then removed it, the
  // user's lines with it; --force did the same; beside a complete output it was removed as a superseded log. Every
  // line is read now (docs/io.md, "Ownership").
  const fs::path dir = scratch("ownership/partial_header_copy");
  REQUIRE(runIn(dir, std::string(kTinyScene) + " --out scene").exit_code == 0);
  writeTinyGrid(dir / "tiny.json");
  const std::string sweep = "sweep --dataset scene --grid tiny.json --quiet --out r.json";
  REQUIRE(runIn(dir, sweep).exit_code == 0);
  const nlohmann::json done = nlohmann::json::parse(fileBytes(dir / "r.json"));
  nlohmann::json header = done;
  for (const char* key : {"maps", "complete", "seconds"}) header.erase(key);
  const std::string users = header.dump() + "\n" + done["maps"][0].dump() + "\nthe user's notes\n";
  fs::rename(dir / "r.json", dir / "done.json");
  writeBytes(dir / "r.json.partial.jsonl", users);
  // The user's file byte-identical, no r.json, nothing left beside them.
  refusedWithAndWithoutForce(dir, sweep, "r.json.partial.jsonl: line 3 is not a line occsweep wrote (bytes were "
                                         "written into the log); occsweep never resumes from, replaces or removes it "
                                         "(even with --force)");
  // Lines a hostile pass put in a copied header's log: JSON that is no map (old binary: skipped, then removed with
  // the log), and occsweep's own map line under another map's index (old binary: exit 0, results that results check
  // refuses).
  writeBytes(dir / "r.json.partial.jsonl", header.dump() + "\n{\"mine\": 1}\n");
  refusedWithAndWithoutForce(dir, sweep, "r.json.partial.jsonl: line 2 is not a map line occsweep wrote");
  // A grid found by its name (octomap-opt): each resumed map is checked against it.
  const std::string opt = "sweep --dataset scene --grid octomap-opt --quiet --out o.json";
  REQUIRE(runIn(dir, opt).exit_code == 0);
  nlohmann::json opt_header = nlohmann::json::parse(fileBytes(dir / "o.json"));
  nlohmann::json moved = opt_header["maps"][0];
  moved["map_index"] = opt_header["maps"][1]["map_index"];
  for (const char* key : {"maps", "complete", "seconds"}) opt_header.erase(key);
  fs::remove(dir / "o.json");
  writeBytes(dir / "o.json.partial.jsonl", opt_header.dump() + "\n" + moved.dump() + "\n");
  refusedWithAndWithoutForce(dir, opt, "parameters differ from the grid's");
  // The same grid's map lines from a sweep at another resolution under this sweep's header: each a map of the grid,
  // all counting one region, but not this sweep's (hostile pass: exit 0 and results `results check` refuses, or,
  // with every map copied, results of the other sweep under this one's header).
  const std::string coarse_sweep = "sweep --dataset scene --grid octomap-opt --quiet --resolution 0.2 --out coarse.json";
  REQUIRE(runIn(dir, coarse_sweep).exit_code == 0);
  const nlohmann::json coarse = nlohmann::json::parse(fileBytes(dir / "coarse.json"));
  fs::remove(dir / "coarse.json");
  for (const std::size_t copied : {std::size_t(3), coarse["maps"].size()}) {
    INFO(copied << " map lines copied");
    std::string log = opt_header.dump() + "\n";
    for (std::size_t i = 0; i < copied; ++i) log += coarse["maps"][i].dump() + "\n";
    writeBytes(dir / "o.json.partial.jsonl", log);
    refusedWithAndWithoutForce(dir, opt, "o.json.partial.jsonl: its maps count ");
  }
  fs::remove(dir / "o.json.partial.jsonl");
  // A file without a sweep's header.
  writeBytes(dir / "r.json.partial.jsonl", "the user's notes\n");
  refusedWithAndWithoutForce(dir, sweep, "r.json.partial.jsonl: not a partial log of occsweep's (its first line is not "
                                         "a sweep's header)");
  writeBytes(dir / "r.json.partial.jsonl", users);
  // A copy of the header of other work (another grid): --force would replace occsweep's own log of other work.
  REQUIRE(runIn(dir, "sweep --dataset scene --grid octomap-opt --quiet --out other.json").exit_code == 0);
  nlohmann::json other = nlohmann::json::parse(fileBytes(dir / "other.json"));
  for (const char* key : {"maps", "complete", "seconds"}) other.erase(key);
  fs::remove(dir / "other.json");
  const std::string others = other.dump() + "\nthe user's notes\n";
  writeBytes(dir / "r.json.partial.jsonl", others);
  const CommandResult forced = runIn(dir, sweep + " --force");
  INFO(forced.output);
  CHECK(forced.exit_code == 2);
  CHECK(mentions(forced, "r.json.partial.jsonl: line 2 is not a line occsweep wrote"));
  CHECK(fileBytes(dir / "r.json.partial.jsonl") == others);
  writeBytes(dir / "r.json.partial.jsonl", users);
  fs::copy_file(dir / "done.json", dir / "r.json", fs::copy_options::overwrite_existing);  // returned as it is
  const CommandResult again = runIn(dir, sweep);
  INFO(again.output);
  CHECK(again.exit_code == 0);
  CHECK(fileBytes(dir / "r.json.partial.jsonl") == users);
}


TEST_CASE("a killed sweep's log that a user linked to, or wrote into, is never resumed from, replaced or removed",
          "[ownership]") {
  // Old binary: a hard link's other name was appended to (its "backup" grew by every map resumed), and a line a user
  // appended with >> was skipped and then removed with the log.
  const fs::path dir = scratch("ownership/partial_written_into");
  REQUIRE(runIn(dir, std::string(kTinyScene) + " --out scene").exit_code == 0);
  const std::string sweep = "sweep --dataset scene --grid knn-opt --engine direct --threads 1 --quiet --out r.json";
  const fs::path partial = dir / "r.json.partial.jsonl";
  SECTION("a hard link") {
    killedSweep(dir);
    fs::create_hard_link(partial, dir / "keep.jsonl");
    refusedWithAndWithoutForce(dir, sweep, "r.json.partial.jsonl: has 2 names (a hard link); occsweep never writes "
                                           "into, replaces or removes a file it resumes that has another name");
    fs::remove(dir / "keep.jsonl");  // its one name again: resumed
    const CommandResult resumed = runIn(dir, sweep);
    INFO(resumed.output);
    CHECK(resumed.exit_code == 0);
    CHECK_FALSE(fs::exists(partial));
  }
  SECTION("lines appended") {
    killedSweep(dir);
    { std::ofstream(partial, std::ios::app) << "the user's notes\n"; }
    refusedWithAndWithoutForce(dir, sweep, "is not a line occsweep wrote (bytes were written into the log); occsweep "
                                           "never resumes from, replaces or removes it");
  }
}

TEST_CASE("a line a kill cut is dropped when the sweep resumes, so a second kill leaves a log the next run resumes",
          "[ownership]") {
  // Without the drop, the resumed run's first line was glued to the cut one: after a second kill the log held a line
  // that is not JSON, and was refused as written into by someone else.
  const fs::path dir = scratch("ownership/partial_cut_line");
  REQUIRE(runIn(dir, std::string(kTinyScene) + " --out scene").exit_code == 0);
  const std::string sweep = "sweep --dataset scene --grid knn-opt --engine direct --threads 1 --quiet --out ";
  REQUIRE(runIn(dir, sweep + "reference.json").exit_code == 0);
  killedSweep(dir);
  const fs::path partial = dir / "r.json.partial.jsonl";
  { std::ofstream(partial, std::ios::app) << "{\"map_index\":17,\"params\":{\"k\""; }  // as a kill cuts a line
  const std::string before = fileBytes(partial);
  // Resumed, and killed again once it has logged two more maps.
  const std::size_t lines = std::size_t(std::count(before.begin(), before.end(), '\n'));
  (void)killOnceLogged(dir, sweep + "r.json", partial, lines + 2);
  REQUIRE_FALSE(fs::exists(dir / "r.json"));
  const CommandResult resumed = runIn(dir, sweep + "r.json");
  INFO(resumed.output);
  CHECK(resumed.exit_code == 0);
  CHECK_FALSE(fs::exists(partial));
  const CommandResult same = runIn(dir, "results diff reference.json r.json");
  INFO(same.output);
  CHECK(same.exit_code == 0);
}

TEST_CASE("a sweep whose complete output is there leaves the partial log another sweep is writing", "[ownership]") {
  // Old binary: the second sweep removed the running sweep's log by its name, without its lock; the first then failed
  // on the complete output put at its --out, advising a resume from the log that was gone.
  const fs::path dir = scratch("ownership/superseded_log_running");
  REQUIRE(runIn(dir, "scene --scans 16 --width 64 --height 48 --out big").exit_code == 0);
  const std::string sweep = "sweep --dataset big --grid octomap-opt --engine direct --threads 1 --quiet --out ";
  REQUIRE(runIn(dir, sweep + "done.json").exit_code == 0);
  const fs::path partial = partialOf(dir, "r.json");
  CommandResult second;
  const int first = sweepPausedOnceUnderWay(dir, "r.json", [&] {
    fs::copy_file(dir / "done.json", dir / "r.json");
    second = runIn(dir, sweep + "r.json");
    CHECK(fs::exists(partial));  // the running sweep's, locked: not the second sweep's to remove
  });
  INFO(second.output);
  CHECK(second.exit_code == 0);
  CHECK(first == 2);  // it finds a results file at its --out, created while it ran
  CHECK(fs::exists(partial));  // and keeps its maps for a resume
  fs::remove(dir / "r.json");
  const CommandResult resumed =
      runIn(dir, "sweep --dataset big --grid octomap-opt --engine direct --threads 1 --out r.json");
  INFO(resumed.output);
  CHECK(resumed.exit_code == 0);
  CHECK(mentions(resumed, "resuming "));  // from every map the first sweep finished
  CHECK_FALSE(fs::exists(partial));
}

TEST_CASE("a user's symbolic link at an output's name is never replaced, even with --force and pointing to occsweep's own output",
          "[ownership]") {
  // Old binary: `merge --force` and `compare --json --force` replaced the link with a file (the user's link gone),
  // since the file it points to is occsweep's.
  const fs::path dir = scratch("ownership/symlink_force");
  REQUIRE(runIn(dir, "scene --scans 4 --width 32 --height 24 --out s").exit_code == 0);
  writeTinyGrid(dir / "tiny.json");
  REQUIRE(runIn(dir, "sweep --dataset s --grid tiny.json --quiet --out r.json").exit_code == 0);
  REQUIRE(runIn(dir, "merge r.json --out own.json").exit_code == 0);
  REQUIRE(runIn(dir, "compare r.json --json own-compare.json").exit_code == 0);
  fs::create_symlink("own.json", dir / "link.json");
  fs::create_symlink("own-compare.json", dir / "link-compare.json");
  const std::string own = fileBytes(dir / "own.json"), own_compare = fileBytes(dir / "own-compare.json");
  for (const std::string command : {"merge r.json --out link.json --force", "compare r.json --json link-compare.json --force",
                                    "merge r.json --out link.json"}) {
    INFO(command);
    const CommandResult r = runIn(dir, command);
    INFO(r.output);
    CHECK(r.exit_code == 2);
    CHECK(mentions(r, "is a symbolic link: occsweep never writes through or replaces one"));
    CHECK(fs::is_symlink(fs::symlink_status(dir / "link.json")));
    CHECK(fs::read_symlink(dir / "link.json") == "own.json");
    CHECK(fs::is_symlink(fs::symlink_status(dir / "link-compare.json")));
    CHECK(fileBytes(dir / "own.json") == own);
    CHECK(fileBytes(dir / "own-compare.json") == own_compare);
  }
}

TEST_CASE("an output with a second name (a hard link) is never replaced, even with --force", "[ownership]") {
  // Found by a hostile pass: compare --json, merge, sweep and map replaced such an output with --force, exit 0 (the
  // other name kept the old bytes, but the rule of docs/io.md, "Ownership", refuses both kinds of link).
  const fs::path dir = scratch("ownership/hardlink_force");
  REQUIRE(runIn(dir, "scene --scans 4 --width 32 --height 24 --out s").exit_code == 0);
  writeTinyGrid(dir / "tiny.json");
  REQUIRE(runIn(dir, "sweep --dataset s --grid tiny.json --quiet --out r.json").exit_code == 0);
  REQUIRE(runIn(dir, "merge r.json --out m.json").exit_code == 0);
  REQUIRE(runIn(dir, "compare r.json --json c.json").exit_code == 0);
  REQUIRE(runIn(dir, "map --dataset s --method octomap --out m.ot").exit_code == 0);
  for (const char* name : {"m.json", "c.json", "r.json", "m.ot"})
    fs::create_hard_link(dir / name, dir / (std::string("kept-") + name));
  const auto before = snapshot(dir);
  for (const std::string command : {"merge r.json --out m.json --force", "compare r.json --json c.json --force",
                                    "sweep --dataset s --grid octomap-opt --quiet --out r.json --force",
                                    "map --dataset s --method knn --out m.ot --force"}) {
    const CommandResult r = runIn(dir, command);
    INFO(command << "\n" << r.output);
    CHECK(r.exit_code == 2);
    CHECK(mentions(r, "has 2 names (a hard link): occsweep never replaces a file another name shares"));
    CHECK(snapshot(dir) == before);
  }
}

TEST_CASE("merge --force never writes over one of the files it merges", "[ownership]") {
  // Old binary: `merge s0.json s1.json --out s0.json --force` replaced the shard s0.json with the merge.
  const fs::path dir = scratch("ownership/merge_into_input");
  REQUIRE(runIn(dir, "scene --scans 4 --width 32 --height 24 --out s").exit_code == 0);
  writeTinyGrid(dir / "tiny.json");
  for (const char* shard : {"0", "1"})
    REQUIRE(runIn(dir, "sweep --dataset s --grid tiny.json --quiet --shard " + std::string(shard) + "/2 --out s" + shard +
                           ".json").exit_code == 0);
  const std::string s0 = fileBytes(dir / "s0.json");
  for (const std::string out : {"s0.json", "./s0.json"}) {
    const CommandResult r = runIn(dir, "merge s0.json s1.json --force --out " + out);
    INFO(r.output);
    CHECK(r.exit_code == 2);
    CHECK(mentions(r, "is one of the files to merge"));
    CHECK(fileBytes(dir / "s0.json") == s0);
  }
}

TEST_CASE("a user's file at SQLite's journal names beside a store to be written stays, and nothing is written",
          "[ownership]") {
  // Old binary: a fresh sweep into s.db took a user's s.db.partial-journal for its store's journal and deleted it;
  // a store written beside a user's r.db-journal was one `results check` then refused.
  const fs::path in = inputs("ownership/journals");
  const std::string s = shellQuoted(in) + "/";
  const fs::path dir = scratch("ownership/journals-out");
  // Each named by what SQLite keeps there (old binary: "the journal" for a -wal file too).
  for (const auto& [command, journal, kind] : std::vector<std::tuple<std::string, std::string, std::string>>{
           {"sweep --dataset " + s + "scene --grid " + s + "tiny.json --quiet --out s.db", "s.db.partial-journal",
            "rollback journal"},
           {"sweep --dataset " + s + "scene --grid " + s + "tiny.json --quiet --out t.db", "t.db-wal",
            "write-ahead log"},
           {"sweep --dataset " + s + "scene --grid " + s + "tiny.json --quiet --out u.db", "u.db-shm", "shared memory"},
           {"results export " + s + "oct.json --out r.db", "r.db-journal", "rollback journal"},
           {"merge " + s + "oct.json --out m.db", "m.db-journal", "rollback journal"}}) {
    INFO(command);
    writeBytes(dir / journal, "the user's notes\n");
    const CommandResult r = runIn(dir, command);
    INFO(r.output);
    CHECK(r.exit_code == 2);
    CHECK(mentions(r, journal + ": stands where SQLite keeps the " + kind + " of the store"));
    CHECK(fileBytes(dir / journal) == "the user's notes\n");
    fs::remove(dir / journal);
    CHECK(leftovers(dir).empty());
  }
}

TEST_CASE("a store in SQLite's WAL mode is refused by every reader and nothing is left beside it", "[ownership]") {
  // Old binary: results check and compare opened it, exit 0, and left wal.db-wal and wal.db-shm beside it.
  const fs::path in = inputs("ownership/wal");
  REQUIRE(runIn(in, "results export oct.json --out wal.db").exit_code == 0);
  const CommandResult wal = runShell("python3 -c \"import sqlite3; c = sqlite3.connect('" + (in / "wal.db").string() +
                                     "'); c.execute('pragma journal_mode=wal'); c.close()\"");
  REQUIRE(wal.exit_code == 0);
  const std::string before = fileBytes(in / "wal.db");
  for (const std::string command : {"results check wal.db", "compare wal.db knn.json"}) {
    INFO(command);
    const CommandResult r = runIn(in, command);
    CHECK(r.exit_code == 2);
    CHECK(mentions(r, "WAL journal mode"));
    CHECK_FALSE(fs::exists(in / "wal.db-wal"));
    CHECK_FALSE(fs::exists(in / "wal.db-shm"));
    CHECK(fileBytes(in / "wal.db") == before);
  }
}

TEST_CASE("cluster files are never written through a user's symbolic link, and ranked set names stay in --out",
          "[ownership]") {
  const fs::path in = inputs("ownership/cluster-links");
  const std::string s = shellQuoted(in) + "/";
  const fs::path dir = scratch("ownership/cluster-links-out");
  REQUIRE(runIn(dir, "cluster plan --out p --experiment sweep --dataset " + s + "scene --grid " + s +
                         "tiny.json:1").exit_code == 0);
  writeBytes(dir / "victim.txt", "precious\n");
  // Old binary: run-local wrote its pid through the lock's link into victim.txt, exit 0.
  fs::create_symlink("../victim.txt", dir / "p" / "run-local.lock");
  CommandResult r = runIn(dir, "cluster run-local p");
  CHECK(r.exit_code == 2);
  CHECK(mentions(r, "run-local.lock: is a symbolic link"));
  CHECK(fileBytes(dir / "victim.txt") == "precious\n");
  fs::remove(dir / "p" / "run-local.lock");
  // Old binary: run-local removed a user's file at a task log's name and wrote the task's output there.
  writeBytes(dir / "p" / "logs" / "local-sweep-0.log", "the user's log\n");
  r = runIn(dir, "cluster run-local p");
  CHECK(r.exit_code == 2);
  CHECK(mentions(r, "local-sweep-0.log does not start with occsweep's line"));
  CHECK(fileBytes(dir / "p" / "logs" / "local-sweep-0.log") == "the user's log\n");
  CHECK_FALSE(fs::exists(dir / "p" / "sweeps"));
  fs::remove(dir / "p" / "logs" / "local-sweep-0.log");
  REQUIRE(runIn(dir, "cluster run-local p").exit_code == 0);
  CHECK(fileBytes(dir / "p" / "logs" / "local-sweep-0.log").starts_with("# occsweep cluster run-local: task log\n"));
  // Its own logs are no obstacle to a task that runs again: replaced.
  fs::remove_all(dir / "p" / "sweeps");
  fs::remove_all(dir / "p" / "merged");
  REQUIRE(runIn(dir, "cluster run-local p").exit_code == 0);
  CHECK(fileBytes(dir / "p" / "logs" / "local-sweep-0.log").starts_with("# occsweep cluster run-local: task log\n"));
  // A log with a second name (a user's hard link to keep it) is the user's too, as every reserved file with two names.
  const fs::path log = dir / "p" / "logs" / "local-sweep-0.log";
  fs::create_hard_link(log, dir / "kept.log");
  const std::string kept = fileBytes(log);
  fs::remove_all(dir / "p" / "sweeps");
  fs::remove_all(dir / "p" / "merged");
  r = runIn(dir, "cluster run-local p");
  CHECK(r.exit_code == 2);
  CHECK(mentions(r, "local-sweep-0.log has 2 names"));
  CHECK(fileBytes(dir / "kept.log") == kept);
  fs::remove(log);
  REQUIRE(runIn(dir, "cluster run-local p").exit_code == 0);
  // Old binary: the select task linked "../newname" outside --out.
  fs::create_directories(dir / "gen" / "newname");
  writeBytes(dir / "gen" / "ranking.json", R"({"format": "occsweep-pointcloud-ranking", "sets": [{"folder": )"
                                           R"("../newname", "id": 0}]})");
  r = runIn(dir, "cluster select gen/ranking.json --out sel/d");
  CHECK(r.exit_code == 2);
  CHECK(mentions(r, "gen/ranking.json: sets: folder '../newname' is not a single folder name"));
  CHECK_FALSE(fs::exists(fs::symlink_status(dir / "sel" / "newname")));
  CHECK_FALSE(fs::exists(dir / "sel" / "d"));
  // Old binary: sets x/y and x_y shared one output, and one was never swept.
  r = runIn(dir, "cluster plan --out q --experiment sweep --dataset " + s + "scene --sets x/y x_y --grid " + s +
                     "tiny.json:1");
  CHECK(r.exit_code == 2);
  CHECK(mentions(r, "--sets x/y and x_y would share the plan's outputs"));
  CHECK_FALSE(fs::exists(dir / "q"));
}

TEST_CASE("outputs that collide through a sweep's partial file, or two names of plot's, are refused before any "
          "work", "[ownership]") {
  const fs::path in = inputs("ownership/partial-collide");
  const std::string s = shellQuoted(in) + "/";
  const fs::path dir = scratch("ownership/partial-collide-out");
  // Old binary: the whole sweep ran, then exit 2 "was created while occsweep was writing it", and
  // a.json.partial.jsonl.partial.jsonl was left.
  for (const std::string outs : {"--out a.json.partial.jsonl --out a.json", "--out b.db.partial --out b.db"}) {
    INFO(outs);
    const CommandResult r = runIn(dir, "sweep --dataset " + s + "scene --grid " + s + "tiny.json --grid " + s +
                                           "tiny.json --quiet " + outs);
    CHECK(r.exit_code == 2);
    CHECK(mentions(r, "partial file name one file"));
    CHECK(leftovers(dir).empty());
    CHECK(fs::is_empty(dir));
  }
  // Old binary: plot wrote its data JSON as f.png and said the name "was created".
  const CommandResult r = runIn(dir, "plot improvement " + s + "oct.json " + s + "knn.json --python " +
                                         std::string(kPython) + " --out f.png --json f.png");
  CHECK(r.exit_code == 2);
  CHECK(mentions(r, "--out and --json name one file"));
  CHECK(fs::is_empty(dir));
}

TEST_CASE("a reader that goes away ends nothing half-done: a sweep piped to a closed pipe completes, exit 0",
          "[ownership]") {
  // Old binary: SIGPIPE killed the sweep (exit 141) after its maps and left r.json.partial.jsonl, no r.json.
  const fs::path in = inputs("ownership/sigpipe");
  const std::string s = shellQuoted(in) + "/";
  const fs::path dir = scratch("ownership/sigpipe-out");
  // The pipe's reader has exited before the sweep starts; the sweep's exit code reaches us through fd 3.
  const CommandResult r = runShell("cd " + shellQuoted(dir) + " && exec 3>&1; { sleep 0.3; " +
                                   shellQuoted(cliUnderTest()) + " sweep --dataset " + s + "scene --grid " + s +
                                   "tiny.json --out r.json 2>&1; echo \"exit $?\" >&3; } | true");
  INFO(r.output);
  CHECK(mentions(r, "exit 0"));
  CHECK(fs::exists(dir / "r.json"));
  CHECK_FALSE(fs::exists(dir / "r.json.partial.jsonl"));
}

TEST_CASE("a table is replaced with --force only when it holds the bytes occsweep wrote there, never a file with its "
          "first line", "[ownership]") {
  // Old binary: a thesis.tex whose first line is compare's LaTeX comment and a notes.csv starting with compare's (or
  // export's) CSV header were replaced with --force, exit 0.
  const fs::path in = inputs("ownership/tables");
  const std::string s = shellQuoted(in) + "/";
  const fs::path dir = scratch("ownership/tables-out");
  const std::string compare = "compare " + s + "oct.json " + s + "knn.json --force";
  REQUIRE(runIn(dir, compare + " --latex own.tex --csv own.csv --markdown own.md").exit_code == 0);
  auto userFileLike = [&](const std::string& name) {
    const std::string first = fileBytes(dir / name).substr(0, fileBytes(dir / name).find('\n') + 1);
    writeBytes(dir / ("user-" + name), first + "the user's own text\n");
  };
  for (const std::string name : {"own.tex", "own.csv", "own.md"}) userFileLike(name);
  for (const auto& [flag, name] : std::vector<std::pair<std::string, std::string>>{
           {"--latex", "own.tex"}, {"--csv", "own.csv"}, {"--markdown", "own.md"}}) {
    INFO(name);
    const std::string user = "user-" + name, before = fileBytes(dir / user);
    const CommandResult r = runIn(dir, compare + " " + flag + " " + user);
    CHECK(r.exit_code == 2);
    CHECK(fileBytes(dir / user) == before);
    CHECK(runIn(dir, compare + " " + flag + " " + name).exit_code == 0);  // its own: replaced
  }
  REQUIRE(runIn(dir, "results export " + s + "oct.json --out own-export.csv").exit_code == 0);
  userFileLike("own-export.csv");
  const std::string before = fileBytes(dir / "user-own-export.csv");
  CHECK(runIn(dir, "results export " + s + "oct.json --force --out user-own-export.csv").exit_code == 2);
  CHECK(fileBytes(dir / "user-own-export.csv") == before);
  CHECK(runIn(dir, "results export " + s + "oct.json --force --out own-export.csv").exit_code == 0);
  // Occsweep's own table edited by hand is the user's now.
  writeBytes(dir / "own.tex", fileBytes(dir / "own.tex") + "% my note\n");
  CHECK(runIn(dir, compare + " --latex own.tex").exit_code == 2);
  CHECK(fileBytes(dir / "own.tex").ends_with("% my note\n"));
}
