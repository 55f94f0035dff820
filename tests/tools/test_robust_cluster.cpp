// cluster plan on user data-set folders, relative grid paths, and run-local killed at random moments: its tasks end
// with it, status sees running shards, a second run-local is refused, and the resumed plan gives the numbers of an
// uninterrupted one (docs/cluster.md, docs/robustness.md "Messages, formats and the cluster").
// OCCSWEEP_TEST_CLI=/path/to/old/occsweep runs the commands of another build.
#include <catch2/catch.hpp>

#include <sys/stat.h>

#include <algorithm>
#include <csignal>
#include <fcntl.h>
#include <fstream>
#include <functional>
#include <iterator>
#include <sstream>
#include <thread>
#include <unistd.h>

#include "occsweep/core/splitmix64.hpp"
#include "occsweep/sweeps/cluster_slurm.hpp"

#include "robust_cli_helpers.hpp"

using namespace occsweep;
namespace fs = std::filesystem;
using Catch::Matchers::Contains;
using namespace std::chrono_literals;

namespace {

void makeScene(const fs::path& out, int seed) {
  const auto r = test::runCli("scene --out " + out.string() + " --seed " + std::to_string(seed) +
                              " --scans 6 --width 32 --height 16");
  REQUIRE(r.exit_code == 0);
}

/// A small OctoMap grid (4 maps of 2 thresholds), written as a file: the plan names it by a relative path.
void writeSmallGrid(const fs::path& file) {
  fs::create_directories(file.parent_path());
  std::ofstream(file) << R"({"name": "small-octomap", "method": "octomap", "parameters": {
    "p_max": {"value": 0.97}, "p_min": {"value": 0.12}, "p_h": {"min": 0.6, "max": 0.9, "step": 0.3},
    "p_m": {"min": 0.2, "max": 0.4, "step": 0.2}, "p_t": {"step": 0.3}}})";
}

/// run-local started in its own process group (so that the test can always clean up what it started), output to
/// `log`.
pid_t startRunLocal(const fs::path& plan, const fs::path& log, int threads) {
  const std::string cli = test::cliUnderTest(), dir = plan.string(), j = std::to_string(threads);
  const pid_t pid = test::startChildProgram([&] {
    ::setpgid(0, 0);
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
    ::dup2(fd, STDOUT_FILENO);
    ::dup2(fd, STDERR_FILENO);
    ::execl(cli.c_str(), cli.c_str(), "cluster", "run-local", dir.c_str(), "--threads", j.c_str(), nullptr);
  });
  REQUIRE(pid >= 0);
  ::setpgid(pid, pid);
  return pid;
}

/// Whether the process has begun to exit (PF_EXITING in /proc/PID/stat's flags): it runs no more code.
bool exiting(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  const std::string stat((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto comm_end = stat.rfind(')');  // the command name may hold spaces and parentheses
  if (comm_end == std::string::npos) return true;  // gone meanwhile
  std::istringstream fields(stat.substr(comm_end + 1));
  std::string state, ppid, pgrp, session, tty, tpgid;
  unsigned long flags = 0;
  fields >> state >> ppid >> pgrp >> session >> tty >> tpgid >> flags;
  constexpr unsigned long kPfExiting = 0x4;  // include/linux/sched.h
  return (flags & kPfExiting) != 0;
}

/// Processes whose working folder is `dir`: run-local's tasks run there, and nothing else does.
std::vector<pid_t> processesIn(const fs::path& dir) {
  std::vector<pid_t> out;
  for (const auto& e : fs::directory_iterator("/proc")) {
    const std::string name = e.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    std::error_code ec;
    const auto cwd = fs::read_symlink(e.path() / "cwd", ec);  // fails for zombies and ended processes
    if (!ec && fs::equivalent(cwd, dir, ec)) out.push_back(pid_t(std::stol(name)));
  }
  return out;
}

/// Waits up to `limit` for the processes in `dir` to end; returns those that still run. One that has begun to exit
/// is waited for up to 10 s more and never counted: it runs no more code, but its folder stays readable until its
/// memory is released, which for an ASan build (terabytes of mapped shadow) took over a second under load.
std::vector<pid_t> survivorsAfter(const fs::path& dir, std::chrono::milliseconds limit) {
  const auto start = std::chrono::steady_clock::now();
  auto left = processesIn(dir);
  while (!left.empty()) {
    const auto waited = std::chrono::steady_clock::now() - start;
    const bool running = std::any_of(left.begin(), left.end(), [](pid_t p) { return !exiting(p); });
    if (waited >= limit && (running || waited >= limit + 10s)) break;
    std::this_thread::sleep_for(50ms);
    left = processesIn(dir);
  }
  std::erase_if(left, [](pid_t p) { return exiting(p); });
  return left;
}

/// Ends whatever the test started in `dir` and is still there (only after a failed check).
void endLeftovers(const fs::path& dir) {
  for (pid_t pid : processesIn(dir)) ::kill(pid, SIGKILL);
}

int waitExit(pid_t pid) {
  int status = 0;
  ::waitpid(pid, &status, 0);
  return status;
}

/// What planWith plans over: the data sets A and B (seeds 1 and 2) and grids/small.json, in `dir`.
void makePlanInputs(const fs::path& dir) {
  makeScene(dir / "A", 1);
  makeScene(dir / "B", 2);
  writeSmallGrid(dir / "grids" / "small.json");
}

std::string planWith(const std::string& plan, const std::string& extra = "") {
  return "cluster plan --out " + plan + " --experiment sweep --dataset A B --grid grids/small.json:2" + extra;
}

}  // namespace

TEST_CASE("the survivor check sees a running process as running and a reaped one as gone") {
  CHECK_FALSE(exiting(::getpid()));
  const pid_t child = ::fork();
  REQUIRE(child >= 0);
  if (child == 0) {
    ::pause();  // runs until killed
    ::_exit(0);
  }
  CHECK_FALSE(exiting(child));
  ::kill(child, SIGKILL);
  (void)waitExit(child);
  CHECK(exiting(child));  // reaped: no /proc entry
}

TEST_CASE("cluster plan --experiment sweep takes user data-set folders without --sets, and relative grid paths") {
  const fs::path dir = test::scratch("robust-cluster-plan");
  makePlanInputs(dir);
  auto r = test::runIn(dir, planWith("p"));
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const ClusterPlan p = readPlan(dir / "p");
  for (const auto& t : stageNamed(p, "sweep").tasks) {
    CHECK((t.argv.at(3) == fs::absolute(dir / "A").string() || t.argv.at(3) == fs::absolute(dir / "B").string()));
    CHECK(t.argv.at(5) == (dir / "grids" / "small.json").string());  // resolved at plan time
  }
  r = test::runIn(dir, "cluster run-local p --threads 2");
  INFO(r.output);
  CHECK(r.exit_code == 0);
  r = test::runIn(dir, "cluster status p");
  INFO(r.output);
  CHECK(r.exit_code == 0);
  CHECK(fs::exists(dir / "p" / "merged" / "A" / "small-octomap.json"));
}

TEST_CASE("cluster run-local --quiet prints no progress and no stage summary, and still names a failure") {
  const fs::path dir = test::scratch("robust-cluster-quiet");
  makePlanInputs(dir);
  for (const char* plan : {"loud", "quiet"}) REQUIRE(test::runIn(dir, planWith(plan)).exit_code == 0);
  auto r = test::runIn(dir, "cluster run-local loud --threads 2");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK_THAT(r.output, Contains("tasks succeeded in"));
  r = test::runIn(dir, "cluster run-local quiet --threads 2 --quiet");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK(r.output.empty());
  CHECK(fs::exists(dir / "quiet" / "merged" / "A" / "small-octomap.json"));
  r = test::runIn(dir, "cluster run-local quiet --quiet");  // nothing left to run: not even "all N tasks done"
  INFO(r.output);
  CHECK(r.exit_code == 0);
  CHECK(r.output.empty());
  // A failure is printed however quiet: the merged file removed and made unwritable by a folder in its place.
  fs::remove(dir / "quiet" / "merged" / "A" / "small-octomap.json");
  fs::create_directories(dir / "quiet" / "merged" / "A" / "small-octomap.json" / "in-the-way");
  r = test::runIn(dir, "cluster run-local quiet --quiet");
  INFO(r.output);
  CHECK(r.exit_code == 1);
  CHECK_THAT(r.output, Contains("failed"));
}

TEST_CASE("status sees run-local's running shards, a second run-local is refused, SIGKILL ends the tasks too") {
  const fs::path dir = test::scratch("robust-cluster-running");
  makePlanInputs(dir);
  // Every task starts 10 s late (bash's read with a timeout, then exec: one process, which keeps the death signal).
  const fs::path slow = dir / "slow-occsweep.sh";
  std::ofstream(slow) << "#!/bin/bash\nread -t 10 <> <(:)\nexec " << test::cliUnderTest() << " \"$@\"\n";
  fs::permissions(slow, fs::perms::owner_all);
  REQUIRE(test::runIn(dir, planWith("p", " --occsweep " + slow.string())).exit_code == 0);
  const fs::path plan = dir / "p";
  const pid_t first = startRunLocal(plan, dir / "first.log", 2);
  auto until = std::chrono::steady_clock::now() + 10s;
  while (processesIn(plan).size() < 2 && std::chrono::steady_clock::now() < until) std::this_thread::sleep_for(20ms);
  std::this_thread::sleep_for(300ms);  // the `<(:)` of the delay, a short-lived subshell, is gone by then
  REQUIRE(processesIn(plan).size() == 2);

  auto r = test::runIn(dir, "cluster status p");
  INFO(r.output);
  CHECK(r.exit_code == 1);
  CHECK_THAT(r.output, Contains("stage sweep: 4 tasks: 0 done, 2 running,"));
  CHECK_THAT(r.output, Contains("run-local pid "));
  r = test::runIn(dir, "cluster run-local p --threads 2");
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.output, Contains("another `cluster run-local` (pid " + std::to_string(first) + ")"));
  CHECK(processesIn(plan).size() == 2);  // the second one started nothing

  ::kill(first, SIGKILL);
  CHECK(WTERMSIG(waitExit(first)) == SIGKILL);
  const auto left = survivorsAfter(plan, 1500ms);  // well before the 10 s delay ends
  CHECK(left.empty());
  endLeftovers(plan);
  r = test::runIn(dir, "cluster status p");
  INFO(r.output);
  CHECK_THAT(r.output, Contains("0 running"));
}

TEST_CASE("run-local killed 24 times at random moments: no task survives, no output is partial, same numbers") {
  const fs::path dir = test::scratch("robust-cluster-kills");
  makePlanInputs(dir);
  REQUIRE(test::runIn(dir, planWith("whole")).exit_code == 0);
  const fs::path whole = dir / "whole", killed = dir / "killed";

  // The uninterrupted run, and its duration: the kills fall within it.
  const auto start = std::chrono::steady_clock::now();
  REQUIRE(waitExit(startRunLocal(whole, dir / "whole.log", 2)) == 0);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  INFO("uninterrupted run: " << seconds << " s");

  // Cycles: a fresh plan, killed and started again until a run finishes it, then its numbers checked; until 24
  // kills have hit a running run-local.
  SplitMix64 rng(13);
  const int signals[] = {SIGTERM, SIGINT, SIGKILL};
  int kills = 0;
  for (int cycle = 0; kills < 24 && cycle < 40; ++cycle) {
    fs::remove_all(killed);
    REQUIRE(test::runIn(dir, planWith("killed")).exit_code == 0);
    const ClusterPlan p = readPlan(killed);
    for (int round = 0;; ++round) {
      const int signal = signals[kills % 3];
      const pid_t pid = startRunLocal(killed, dir / "killed.log", 2);
      std::this_thread::sleep_for(std::chrono::duration<double>(rng.uniform() * seconds * 0.6));
      ::kill(pid, signal);
      const int status = waitExit(pid);
      INFO("cycle " << cycle << " round " << round << ", signal " << signal << ", run-local wait status " << status);
      // Stopped by SIGTERM or SIGINT, run-local ends its tasks and waits for them before it dies itself; after a
      // SIGKILL the kernel sends them SIGTERM, which takes them a moment.
      const auto left = survivorsAfter(killed, signal == SIGKILL ? 1000ms : 0ms);
      CHECK(left.empty());
      endLeftovers(killed);
      // Every output on disk is either absent or complete (Done or, once an input was redone, Stale).
      for (const auto& row : planStatus(p, killed, {}, {}))
        for (const auto& t : row) {
          INFO(stateName(t.state) << ": " << t.detail);
          CHECK((t.state == TaskState::Done || t.state == TaskState::Missing || t.state == TaskState::Stale));
        }
      // Killed: it died of the signal, or (a signal met before run-local's own handlers are installed) occsweep's
      // interrupt cleaning exited 128 + signal, as every command does (docs/robustness.md).
      if ((WIFSIGNALED(status) && WTERMSIG(status) == signal) ||
          (WIFEXITED(status) && WEXITSTATUS(status) == 128 + signal)) {
        ++kills;
        continue;
      }
      REQUIRE(WIFEXITED(status));  // finished before the signal came
      REQUIRE(WEXITSTATUS(status) == 0);
      break;
    }
    for (const char* d : {"A", "B"}) {
      const fs::path file = fs::path("merged") / d / "small-octomap.json";
      CHECK(resultDifferences(readResults(whole / file), readResults(killed / file)).empty());
    }
    CHECK(test::runIn(dir, "cluster status killed").exit_code == 0);
  }
  CHECK(kills >= 24);
}

namespace {

/// The small grid under another `name` (as given, a JSON string's contents).
void writeGridNamed(const fs::path& file, const std::string& name) {
  fs::create_directories(file.parent_path());
  std::ofstream(file) << R"({"name": ")" << name << R"(", "method": "octomap", "parameters": {
    "p_max": {"value": 0.97}, "p_min": {"value": 0.12}, "p_h": {"min": 0.6, "max": 0.9, "step": 0.3},
    "p_m": {"min": 0.2, "max": 0.4, "step": 0.2}, "p_t": {"step": 0.3}}})";
}

}  // namespace

// docs/cluster.md, "Outputs stay in the plan folder": a grid's name joins output paths, so a name that is not one
// safe path component is refused at planning, naming the grid file and the field; a hand-edited plan.json whose
// output leaves the folder is refused by run-local. Oracle: the user's victim.json beside the plan folder is
// byte-identical afterwards (an older build put the merged results there, deleting it first).
TEST_CASE("a grid named ../../../victim or a plan output outside the plan folder never touches a user's file") {
  const fs::path dir = test::scratch("robust-cluster-escape");
  makeScene(dir / "A", 1);
  const std::string victim = "{\"mine\": \"not occsweep's\"}\n";
  std::ofstream(dir / "victim.json") << victim;
  writeSmallGrid(dir / "grids" / "small.json");
  for (const std::string name : {"../../../victim", "a/b", ".hidden", "..", "tab\\there"}) {
    INFO("grid name " << name);
    writeGridNamed(dir / "grids" / "evil.json", name);
    auto r = test::runIn(dir, "cluster plan --out p --experiment sweep --dataset A --grid "
                              "grids/small.json:1 --grid grids/evil.json:1");
    INFO(r.output);
    // Twice: the second run finds merged/A made by the first, through which ../../../victim.json resolves.
    for (int run = 0; run < 2 && r.exit_code == 0; ++run) (void)test::runIn(dir, "cluster run-local p --threads 2");
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.output, Contains("evil.json: name: must be a single path component"));
    CHECK_FALSE(fs::exists(dir / "p" / "plan.json"));
    CHECK(test::bytesOf(dir / "victim.json") == victim);
    fs::remove_all(dir / "p");
  }
  // A plan made well, then edited by hand so that the merge writes ../victim.json: refused, nothing run.
  auto r = test::runIn(dir, "cluster plan --out p --experiment sweep --dataset A --grid grids/small.json:1");
  REQUIRE(r.exit_code == 0);
  std::string plan = test::bytesOf(dir / "p" / "plan.json");
  const std::string merged = "\"merged/A/small-octomap.json\"";
  REQUIRE(plan.find(merged) != std::string::npos);
  for (auto at = plan.find(merged); at != std::string::npos; at = plan.find(merged))  // argv, output, inputs
    plan.replace(at, merged.size(), "\"merged/../../victim.json\"");
  std::ofstream(dir / "p" / "plan.json", std::ios::trunc) << plan;
  r = test::runIn(dir, "cluster run-local p --threads 2");
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.output, Contains("plan.json: stages[merge].tasks[].output: must be a relative path inside the plan"));
  CHECK_FALSE(fs::exists(dir / "p" / "sweeps"));
  CHECK(test::bytesOf(dir / "victim.json") == victim);
}

// docs/io.md, "Ownership": run-local removes a running marker only when it starts with run-local's mark line;
// a user's file named like one (even one holding a dead process's number) stays byte-identical.
TEST_CASE("run-local removes only the running markers it wrote, never a user's file named like one") {
  // Old binary: every regular `running/*.pid` holding a number was removed, the user's too, exit 0.
  const fs::path dir = test::scratch("robust-cluster-markers");
  makePlanInputs(dir);
  REQUIRE(test::runIn(dir, planWith("p")).exit_code == 0);
  const fs::path running = dir / "p" / "running";
  fs::create_directories(running);
  const std::string mine = "999999\n";
  for (const char* name : {"sweep-0.pid", "notes.pid", "sweep-2.pid"}) std::ofstream(running / name) << mine;
  std::ofstream(running / "sweep-2.pid", std::ios::trunc) << "";  // an empty file is no marker either
  // What a killed run-local leaves: its mark line and a task's pid no process has any more.
  std::ofstream(running / "sweep-1.pid") << "# occsweep cluster run-local: running task\n999999\n";
  auto r = test::runIn(dir, "cluster run-local p --threads 2");
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.output, Contains("sweep-0.pid: does not start with occsweep's line"));
  CHECK_FALSE(fs::exists(dir / "p" / "sweeps"));  // no task started
  CHECK(test::bytesOf(running / "sweep-0.pid") == mine);
  CHECK(test::bytesOf(running / "notes.pid") == mine);
  CHECK(test::bytesOf(running / "sweep-2.pid").empty());
  CHECK_FALSE(fs::exists(running / "sweep-1.pid"));  // stale and run-local's: removed
  fs::remove(running / "sweep-2.pid");
  // Moved away, the plan runs; the file at a name no task uses stays as it was.
  fs::rename(running / "sweep-0.pid", dir / "sweep-0.pid");
  r = test::runIn(dir, "cluster run-local p --threads 2");
  INFO(r.output);
  CHECK(r.exit_code == 0);
  CHECK(test::bytesOf(running / "notes.pid") == mine);
  CHECK(test::listing(running) == std::vector<std::string>{"notes.pid"});  // its own markers gone with their tasks
}

TEST_CASE("run-local and status never block on a FIFO, never follow a link out of the plan, never write into a user's "
          "file at the lock's name") {
  const fs::path dir = test::scratch("robust-cluster-fifo");
  makePlanInputs(dir);
  REQUIRE(test::runIn(dir, planWith("p")).exit_code == 0);
  const fs::path running = dir / "p" / "running";
  fs::create_directories(running);
  // Old binary: status and run-local opened the marker to read a pid, and waited for a writer forever.
  REQUIRE(::mkfifo((running / "sweep-0.pid").c_str(), 0600) == 0);
  const std::string cli = test::shellQuoted(test::cliUnderTest());
  auto r = test::runShell("cd " + test::shellQuoted(dir) + " && timeout 120 " + cli + " cluster status p 2>&1");
  INFO(r.output);
  CHECK(r.exit_code != 124);  // timeout's code: it blocked
  r = test::runShell("cd " + test::shellQuoted(dir) + " && timeout 120 " + cli + " cluster run-local p 2>&1");
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.output, Contains("sweep-0.pid: is not a regular file"));
  CHECK(fs::is_fifo(fs::symlink_status(running / "sweep-0.pid")));
  fs::remove(running / "sweep-0.pid");
  // Old binary: a link at logs/ took the task logs out of the plan folder.
  fs::create_directories(dir / "elsewhere");
  fs::remove_all(dir / "p" / "logs");
  fs::create_directory_symlink("../elsewhere", dir / "p" / "logs");
  r = test::runIn(dir, "cluster run-local p");
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.output, Contains("logs: is a symbolic link"));
  CHECK(test::listing(dir / "elsewhere").empty());
  fs::remove(dir / "p" / "logs");
  r = test::runIn(dir, "cluster run-local p");
  INFO(r.output);
  CHECK(r.exit_code == 0);
  // Old binary: a user's file at the lock's name (here a hard link to their notes) was truncated and given a pid.
  fs::remove(dir / "p" / "run-local.lock");
  std::ofstream(dir / "notes.txt") << "the user's notes\n";
  fs::create_hard_link(dir / "notes.txt", dir / "p" / "run-local.lock");
  fs::remove_all(dir / "p" / "merged");
  r = test::runIn(dir, "cluster run-local p");
  INFO(r.output);
  CHECK(r.exit_code == 0);
  CHECK(test::bytesOf(dir / "notes.txt") == "the user's notes\n");
}

// Old binary: `cluster submit` opened a FIFO at a stage's script to compare it with the plan's and waited for a
// writer forever. It reads every script before it calls sbatch, so no Slurm is needed to see it.
TEST_CASE("cluster submit refuses a FIFO at a stage's script, submissions.jsonl or plan.json at once, naming it") {
  const fs::path dir = test::scratch("robust-cluster-submit-fifo");
  makePlanInputs(dir);
  REQUIRE(test::runIn(dir, planWith("p")).exit_code == 0);
  const std::string script = "slurm/" + readPlan(dir / "p").stages.at(0).name + ".sbatch";
  for (const std::string& name : {script, std::string("submissions.jsonl"), std::string("plan.json")}) {
    INFO(name);
    const fs::path entry = dir / "p" / name, kept = dir / "kept";
    const bool existed = fs::exists(entry);
    if (existed) fs::rename(entry, kept);
    REQUIRE(::mkfifo(entry.c_str(), 0600) == 0);
    const auto r = test::runShell("cd " + test::shellQuoted(dir) + " && timeout 30 " +
                                  test::shellQuoted(test::cliUnderTest()) + " cluster submit p 2>&1");
    INFO(r.output);
    CHECK(r.exit_code == 2);  // not timeout's 124: it did not block
    CHECK_THAT(r.output, Contains("p/" + name + ": is a FIFO (named pipe), expected a regular file"));
    fs::remove(entry);
    if (existed) fs::rename(kept, entry);
  }
}

// docs/cluster.md: `cluster plan --force` is every command's --force: it replaces occsweep's own earlier plan
// (proven by plan.json's own "format" field) and nothing else; a user's plan.json is refused with or without it,
// byte-identical afterwards, and no plan file is written beside it. --replace is no flag.
TEST_CASE("cluster plan --force replaces only occsweep's own plan, a user's plan.json stays byte-identical") {
  const fs::path dir = test::scratch("robust-cluster-force");
  makeScene(dir / "A", 1);
  writeSmallGrid(dir / "grids" / "small.json");
  const std::string plan = "cluster plan --out p --experiment sweep --dataset A --grid grids/small.json:";
  fs::create_directories(dir / "p");
  const std::string mine = "{\"my\": \"own plan, not occsweep's\"}\n";
  std::ofstream(dir / "p" / "plan.json") << mine;
  for (const char* flag : {"", " --force", " --replace"}) {
    INFO("flag '" << flag << "'");
    const auto r = test::runIn(dir, plan + "2" + flag);
    INFO(r.output);
    CHECK(r.exit_code == 2);
    CHECK(test::bytesOf(dir / "p" / "plan.json") == mine);
    CHECK(test::listing(dir / "p") == std::vector<std::string>{"plan.json"});
    if (std::string(flag) != " --replace") CHECK_THAT(r.output, Contains("not an occsweep plan"));
    else CHECK_THAT(r.output, Contains("unknown option --replace"));
  }
  // occsweep's own plan: the same plan again is fine, a different one needs --force, which replaces it.
  fs::remove(dir / "p" / "plan.json");
  REQUIRE(test::runIn(dir, plan + "2").exit_code == 0);
  REQUIRE(test::runIn(dir, plan + "2").exit_code == 0);
  const std::string two = test::bytesOf(dir / "p" / "plan.json");
  auto r = test::runIn(dir, plan + "1");
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.output, Contains("a different plan is already there (--force replaces it"));
  CHECK(test::bytesOf(dir / "p" / "plan.json") == two);
  r = test::runIn(dir, plan + "1 --force");
  CHECK(r.exit_code == 0);
  CHECK(readPlan(dir / "p").stages.at(0).tasks.size() == 1);
}

// docs/cluster.md, "Options": the plan's shards and merges are JSON results files, which `sweep` refuses past
// 200,000 combinations; an ungrouped grid past that is refused at planning (an older build planned it, and every
// task would have failed, or run out of memory, on the cluster).
TEST_CASE("cluster plan never replaces a Slurm script it did not write: a user's file, or its own edited by hand") {
  // Old binary: both were overwritten, exit 0 (only plan.json was checked).
  const fs::path dir = test::scratch("robust-cluster-scripts");
  makeScene(dir / "A", 1);
  writeSmallGrid(dir / "grids" / "small.json");
  const std::string plan = "cluster plan --experiment sweep --dataset A --grid grids/small.json:";
  REQUIRE(test::runIn(dir, plan + "2 --out probe").exit_code == 0);
  const std::string stage = readPlan(dir / "probe").stages.at(0).name;
  const std::string script = "slurm/" + stage + ".sbatch";
  // A folder of the user's that already holds a script by that name.
  fs::create_directories(dir / "p" / "slurm");
  const std::string mine = "#!/bin/bash\n# my own job script\n";
  std::ofstream(dir / "p" / script) << mine;
  for (const char* flag : {"", " --force"}) {
    INFO("flag '" << flag << "'");
    const auto r = test::runIn(dir, plan + "2 --out p" + flag);
    INFO(r.output);
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.output, Contains(script) && Contains("not the script occsweep wrote for the plan there"));
    CHECK(test::bytesOf(dir / "p" / script) == mine);
    CHECK(test::listing(dir / "p") == std::vector<std::string>{"slurm", script});  // no plan.json, no logs/
  }
  // occsweep's own plan whose script the user edited: a new plan with --force keeps the edit and the old plan.
  REQUIRE(test::runIn(dir, plan + "2 --out q").exit_code == 0);
  const std::string written = test::bytesOf(dir / "q" / script), two = test::bytesOf(dir / "q" / "plan.json");
  std::ofstream(dir / "q" / script, std::ios::app) << "module load gcc\n";
  const auto r = test::runIn(dir, plan + "1 --out q --force");
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.output, Contains(script));
  CHECK(test::bytesOf(dir / "q" / script) == written + "module load gcc\n");
  CHECK(test::bytesOf(dir / "q" / "plan.json") == two);
  // Its own script as written is replaced, as --force says.
  std::ofstream(dir / "q" / script) << written;
  CHECK(test::runIn(dir, plan + "1 --out q --force").exit_code == 0);
  CHECK(readPlan(dir / "q").stages.at(0).tasks.size() == 1);
  // A symbolic link at plan.json, or a slurm/ folder linked to a user's folder: refused even with --force, both
  // untouched (old binary: plan.json's link became a file, and the scripts went into the user's folder).
  fs::create_directories(dir / "l");
  fs::rename(dir / "q" / "plan.json", dir / "their-plan.json");
  fs::create_symlink("../their-plan.json", dir / "q" / "plan.json");
  fs::create_directories(dir / "theirs");
  fs::create_directory_symlink("../theirs", dir / "l" / "slurm");
  for (const char* out : {"q", "l"}) {
    INFO(out);
    const auto linked = test::runIn(dir, plan + "2 --force --out " + out);
    INFO(linked.output);
    CHECK(linked.exit_code == 2);
    CHECK_THAT(linked.output, Contains("is a symbolic link: occsweep never writes through or replaces one"));
  }
  CHECK(fs::is_symlink(fs::symlink_status(dir / "q" / "plan.json")));
  CHECK(fs::is_empty(dir / "theirs"));
}

TEST_CASE("cluster plan --force refuses to replace a plan whose outputs the new plan's other commands would take as done") {
  // Old binary: re-planned with other sweep settings, every old shard passed the new tasks' check and counted as done,
  // and the report printed the old settings' numbers for the new plan.
  const fs::path dir = test::scratch("robust-cluster-stale");
  makeScene(dir / "A", 1);
  writeSmallGrid(dir / "grids" / "small.json");
  const std::string plan = "cluster plan --out p --experiment sweep --dataset A --grid grids/small.json:1";
  REQUIRE(test::runIn(dir, plan).exit_code == 0);
  const auto ran = test::runIn(dir, "cluster run-local p");
  INFO(ran.output);
  REQUIRE(ran.exit_code == 0);
  const std::string before = test::bytesOf(dir / "p" / "plan.json");
  const auto r = test::runIn(dir, plan + " --sweep-args=--s-c,2 --force");
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.output, Contains("an output of the plan being replaced") && Contains("would take as done"));
  CHECK(test::bytesOf(dir / "p" / "plan.json") == before);
  // The same plan again is fine: its outputs are its own.
  CHECK(test::runIn(dir, plan + " --force").exit_code == 0);
}

TEST_CASE("cluster plan refuses an ungrouped grid past a JSON results file's combinations, whatever its shards") {
  const fs::path dir = test::scratch("robust-cluster-json-grid");
  makeScene(dir / "A", 1);
  std::ofstream(dir / "fine.json") << R"({"name": "fine-pt", "method": "octomap", "parameters": {
    "p_max": {"value": 0.98}, "p_min": {"value": 0.02}, "p_h": {"min": 0.5, "max": 0.86, "step": 0.12}, "p_m": {"value": 0.2},
    "p_t": {"step": 0.000016}}})";
  for (const char* shards : {"1", "4"}) {
    const auto r =
        test::runIn(dir, std::string("cluster plan --out p --experiment sweep --dataset A --grid fine.json:") + shards);
    INFO(r.output);
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.output,
               Contains("grid fine.json: 240004 combinations, more than the 200000 a JSON results file holds"));
    CHECK_FALSE(fs::exists(dir / "p"));
  }
}

// docs/cluster.md, "Measured tasks": run-local appends to its own measured.jsonl only. Old binary: a user's file (or
// a hard link to one outside the plan) at that name got run-local's records appended, exit 0.
TEST_CASE("run-local appends its measurements to its own measured.jsonl only, never to a user's file or a link") {
  const fs::path dir = test::scratch("robust-cluster-measured");
  REQUIRE(test::runIn(dir, "scene --scans 2 --width 8 --height 6 --out ds").exit_code == 0);
  std::ofstream(dir / "mine.txt") << "my own measurements\n";
  const std::string mine = test::bytesOf(dir / "mine.txt");
  const std::vector<std::pair<std::string, std::function<void(const fs::path&)>>> entries = {
      {"holds a line that is not a task measurement", [&](const fs::path& at) { fs::copy_file(dir / "mine.txt", at); }},
      {"has 2 hard links", [&](const fs::path& at) { fs::create_hard_link(dir / "mine.txt", at); }},
      {"is a symbolic link", [&](const fs::path& at) { fs::create_symlink(dir / "mine.txt", at); }},
      {"is not a regular file", [&](const fs::path& at) { REQUIRE(::mkfifo(at.c_str(), 0644) == 0); }},
  };
  int n = 0;
  for (const auto& [why, make] : entries) {
    const std::string plan = "p" + std::to_string(n++);
    REQUIRE(test::runIn(dir, "cluster plan --experiment sweep --dataset ds --grid octomap-opt:1 --out " + plan)
                .exit_code == 0);
    make(dir / plan / "measured.jsonl");
    const auto r = test::runIn(dir, "cluster run-local " + plan);
    INFO(why << "\n" << r.output);
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.output, Contains("measured.jsonl: " + why));
    CHECK_THAT(r.output, Contains("move it away"));
    CHECK(test::bytesOf(dir / "mine.txt") == mine);
    CHECK_FALSE(fs::exists(dir / plan / "merged"));  // no task ran
  }
  // Its own file: made by the first run, appended to by the next.
  REQUIRE(test::runIn(dir, "cluster plan --experiment sweep --dataset ds --grid octomap-opt:2 --out own").exit_code == 0);
  REQUIRE(test::runIn(dir, "cluster run-local own").exit_code == 0);
  const std::string first = test::bytesOf(dir / "own" / "measured.jsonl");
  CHECK_FALSE(first.empty());
  fs::remove(dir / "own" / "report" / "comparison.json");  // one task to run again
  const auto again = test::runIn(dir, "cluster run-local own");
  INFO(again.output);
  CHECK(again.exit_code == 0);
  CHECK(test::bytesOf(dir / "own" / "measured.jsonl").size() > first.size());
}
