// Fault test: scene, import, map, sweep and merge killed at seeded random moments (SIGKILL and SIGTERM
// alternately, 20 kills each). After every kill no final output is partial; the next run names what a SIGKILL left
// with the command that removes it, and its output equals an uninterrupted run's (docs/io.md, "Ownership").
#include <catch2/catch.hpp>
#include <chrono>
#include <csignal>
#include <fcntl.h>
#include <functional>
#include <sstream>
#include <nlohmann/json.hpp>
#include <sys/wait.h>
#include <thread>

#include "occsweep/io/child_process.hpp"
#include "occsweep/sweeps/results.hpp"
#include "robust_outputs_helpers.hpp"

namespace fs = std::filesystem;
using namespace occsweep;
using namespace occsweep::test;
using Clock = std::chrono::steady_clock;

namespace {

constexpr int kKills = 20;

/// Starts `occsweep ARGS...` in `cwd` without a shell (so that the signal reaches occsweep itself).
pid_t start(const fs::path& cwd, const std::vector<std::string>& args) {
  const std::string binary = cliUnderTest();
  std::vector<char*> argv{const_cast<char*>(binary.c_str())};
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  // A kill that comes before exec ends the child, never Catch's handler in it (startChildProgram).
  return startChildProgram([&] {
    if (::chdir(cwd.c_str()) != 0) return;
    const int null = ::open("/dev/null", O_WRONLY);
    ::dup2(null, 1);
    ::dup2(null, 2);
    ::execv(binary.c_str(), argv.data());
  });
}

int wait(pid_t pid) {
  int status = 0;
  ::waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

/// Seconds an uninterrupted run takes.
double timed(const fs::path& cwd, const std::vector<std::string>& args) {
  const auto t0 = Clock::now();
  REQUIRE(wait(start(cwd, args)) == 0);
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

/// Runs `args` and kills it after a seeded random delay within 1.2 times its uninterrupted duration.
void killAtRandom(const fs::path& cwd, const std::vector<std::string>& args, double seconds, SplitMix64& rng, int i) {
  const pid_t pid = start(cwd, args);
  std::this_thread::sleep_for(std::chrono::duration<double>(rng.uniform() * 1.2 * seconds));
  ::kill(pid, i % 2 == 0 ? SIGKILL : SIGTERM);
  wait(pid);
}

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> words;
  std::istringstream in(s);
  for (std::string w; in >> w;) words.push_back(w);
  return words;
}

/// The next run of `args` in `cwd` after a kill: each temporary a SIGKILL left beside its target is named with the
/// command that removes it, then removed as the user would; a SIGTERM leaves none. Returns the run's exit code.
int rerunAfterKill(const fs::path& cwd, const std::vector<std::string>& args) {
  const std::vector<std::string> left = leftovers(cwd);
  std::string line;
  for (const std::string& a : args) line += " " + shellQuoted(a);
  const CommandResult r = runIn(cwd, line);
  INFO(r.output);
  for (const std::string& entry : left) {
    CHECK(r.output.find("rm -r -- ") != std::string::npos);
    CHECK(r.output.find(shellWord((fs::path(".") / fs::path(entry).filename()).string())) != std::string::npos);
    fs::remove_all(entry);
  }
  CHECK(leftovers(cwd).empty());
  return r.exit_code;
}

std::vector<std::string> withForce(std::vector<std::string> args) {
  args.push_back("--force");
  return args;
}

// The settings beside a map, without its build time (the one field that differs between two runs).
nlohmann::json settings(const fs::path& file) {
  auto j = nlohmann::json::parse(fileBytes(file));
  j.erase("build_seconds");
  return j;
}

/// A folder output (scene, import): after each kill the target is absent or whole; the re-run leaves it whole.
void faultTestFolder(const std::string& name, const std::vector<std::string>& args, std::uint64_t seed,
                     const std::function<void(const fs::path&)>& prepare) {
  const fs::path ref = scratch("robust_faults/" + name + "/ref"), run = scratch("robust_faults/" + name + "/run");
  prepare(ref);
  prepare(run);
  const double seconds = timed(ref, args);
  const auto expected = snapshot(ref / "out");
  SplitMix64 rng(seed);
  for (int i = 0; i < kKills; ++i) {
    killAtRandom(run, args, seconds, rng, i);
    if (fs::exists(run / "out")) CHECK(snapshot(run / "out") == expected);  // never partial
    INFO(name << " kill " << i);
    CHECK(rerunAfterKill(run, fs::exists(run / "out") ? withForce(args) : args) == 0);
    CHECK(snapshot(run / "out") == expected);
    fs::remove_all(run / "out");
  }
}

}  // namespace

TEST_CASE("scene killed at random moments: never a partial data set, what a kill left named by the next run", "[faults]") {
  faultTestFolder("scene", split("scene --scans 8 --width 64 --height 48 --out out"), 11, [](const fs::path&) {});
}

TEST_CASE("import killed at random moments: never a partial data set, what a kill left named by the next run", "[faults]") {
  faultTestFolder("import", split("import cloud a.xyz b.xyz c.xyz --out out"), 12, [](const fs::path& dir) {
    for (const char* f : {"a.xyz", "b.xyz", "c.xyz"}) {
      std::ofstream out(dir / f);
      for (int i = 0; i < 3000; ++i) out << 1 + 0.001 * i << ' ' << 0.5 << ' ' << 0.0007 * i << '\n';
    }
  });
}

TEST_CASE("map killed at random moments: never a partial .ot, the re-run equals an uninterrupted run", "[faults]") {
  const fs::path dir = scratch("robust_faults/map");
  REQUIRE(runIn(dir, "scene --scans 8 --width 64 --height 48 --out scene").exit_code == 0);
  const auto args = split("map --dataset scene --method knn --out m.ot");
  const double seconds = timed(dir, split("map --dataset scene --method knn --out ref.ot"));
  const std::string expected = fileBytes(dir / "ref.ot");
  const auto expected_settings = settings(dir / "ref.ot.json");
  SplitMix64 rng(13);
  for (int i = 0; i < kKills; ++i) {
    INFO("map kill " << i);
    killAtRandom(dir, args, seconds, rng, i);
    if (fs::exists(dir / "m.ot")) CHECK(fileBytes(dir / "m.ot") == expected);
    if (fs::exists(dir / "m.ot.json")) CHECK(settings(dir / "m.ot.json") == expected_settings);
    CHECK(rerunAfterKill(dir, fs::exists(dir / "m.ot") ? withForce(args) : args) == 0);
    CHECK(fileBytes(dir / "m.ot") == expected);
    CHECK(settings(dir / "m.ot.json") == expected_settings);
    fs::remove(dir / "m.ot");
    fs::remove(dir / "m.ot.json");
  }
}

TEST_CASE("sweep and merge killed at random moments: resumed results equal an uninterrupted run's", "[faults]") {
  const fs::path dir = scratch("robust_faults/sweep");
  REQUIRE(runIn(dir, "scene --scans 4 --width 32 --height 24 --out scene").exit_code == 0);  // a sweep of ~0.2 s
  writeTinyGrid(dir / "tiny.json");
  const std::string sweep = "sweep --dataset scene --grid tiny.json --engine direct --threads 1 --quiet";
  const double seconds = timed(dir, split(sweep + " --out ref.json"));
  const ResultsFile expected = readResults(dir / "ref.json");
  SplitMix64 rng(14);
  for (int i = 0; i < kKills; ++i) {
    INFO("sweep kill " << i);
    killAtRandom(dir, split(sweep + " --out r.json"), seconds, rng, i);
    if (fs::exists(dir / "r.json")) CHECK(resultDifferences(expected, readResults(dir / "r.json")).empty());
    CHECK(rerunAfterKill(dir, split(sweep + " --out r.json")) == 0);  // resumes its own partial work
    CHECK(!fs::exists(dir / "r.json.partial.jsonl"));
    CHECK(resultDifferences(expected, readResults(dir / "r.json")).empty());
    fs::remove(dir / "r.json");
  }
  REQUIRE(runIn(dir, sweep + " --shard 0/2 --out s0.json").exit_code == 0);
  REQUIRE(runIn(dir, sweep + " --shard 1/2 --out s1.json").exit_code == 0);
  const auto merge = split("merge s0.json s1.json --out m.json");
  const double merge_seconds = timed(dir, split("merge s0.json s1.json --out mref.json"));
  for (int i = 0; i < kKills; ++i) {
    INFO("merge kill " << i);
    killAtRandom(dir, merge, merge_seconds, rng, i);
    if (fs::exists(dir / "m.json")) CHECK(resultDifferences(expected, readResults(dir / "m.json")).empty());
    CHECK(rerunAfterKill(dir, fs::exists(dir / "m.json") ? withForce(merge) : merge) == 0);
    CHECK(resultDifferences(expected, readResults(dir / "m.json")).empty());
    fs::remove(dir / "m.json");
  }
}
