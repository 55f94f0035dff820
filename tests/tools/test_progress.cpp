// Progress of long work (docs/cli.md, "Progress"): the line's numbers by hand, a sweep into a log that names its
// phases and reports rate and time left every few seconds, and an interrupted sweep that prints the command which
// resumes it. OCCSWEEP_TEST_CLI=/path/to/old/occsweep runs the command cases against another build.
#include <catch2/catch.hpp>

#include <csignal>
#include <fstream>
#include <regex>
#include <thread>

#include "occsweep/sweeps/progress.hpp"
#include "robust_cli_helpers.hpp"

using namespace occsweep;
namespace fs = std::filesystem;
using Catch::Matchers::Contains;

namespace {

// The built-in scene at its default size: 24 scans, about 51,000 points.
fs::path defaultScene() {
  static const fs::path dir = [] {
    const fs::path d = test::processScratch("progress-scene") / "scene";
    REQUIRE(test::runCli("scene --out " + d.string()).exit_code == 0);
    return d;
  }();
  return dir;
}

// The knn-opt grid (450 maps) and octomap-opt (20 maps, liboctomap) swept by the direct engine on one thread: each map
// built from the scans, about 20 s on this project's machines (the log of the case below prints its time).
std::string slowSweep(const fs::path& dir) {
  return "sweep --dataset " + defaultScene().string() + " --grid knn-opt --grid octomap-opt --engine direct " +
         "--threads 1 --out " + (dir / "knn.json").string() + " --out " + (dir / "oct.json").string();
}

// The command line an interrupt printed: "cd FOLDER && COMMAND".
std::string resumeLine(const std::string& log) {
  std::smatch m;
  REQUIRE(std::regex_search(log, m, std::regex("The same command in the same folder resumes it:\n  (cd .*)\n")));
  return m[1].str();
}

// `occsweep ARGS` started in the background, stdout and stderr into `log` (not a terminal): its process id.
pid_t startCli(const std::string& args, const fs::path& log) {
  return test::startShell("exec " + test::shellQuoted(test::cliUnderTest()) + " " + args + " > " +
                          test::shellQuoted(log) + " 2>&1");
}

int exitOf(pid_t child) {
  int status = 0;
  ::waitpid(child, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
}

// `occsweep ARGS` (a sweep) started with its output into `log`, sent `signal` (SIGINT unless said) once it has written
// a progress line (some maps are done and kept), and ended with 128 + signal: its log.
std::string interruptedSweepLog(const std::string& args, const fs::path& log, int signal = SIGINT) {
  const pid_t child = startCli(args, log);
  for (int i = 0; i < 600 && test::bytesOf(log).find("maps/s") == std::string::npos; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  ::kill(child, signal);
  REQUIRE(exitOf(child) == 128 + signal);
  return test::bytesOf(log);
}

}  // namespace

TEST_CASE("a progress line gives counts, percent, rate and time left, by hand") {
  CHECK(progressLine("sweep g on ds", "maps", 1200, 4050, 14.1) ==
        "sweep g on ds: 1200/4050 maps (29.6 %), 85.1 maps/s, 33 s left, 14 s so far");  // 2850 / (1200 / 14.1)
  CHECK(progressLine("stage sweep", "tasks", 0, 7, 3.0) == "stage sweep: 0/7 tasks (0.0 %), 3 s so far");
  CHECK(progressLine("NCA weights", "fits", 40, 40, 250.4) == "NCA weights: 40/40 fits (100.0 %), 0.16 fits/s, "
                                                               "4 min 10 s in all");
  CHECK(progressLine("x", "maps", 30000, 90000, 100.0) == "x: 30000/90000 maps (33.3 %), 300 maps/s, 3 min 20 s left, "
                                                         "1 min 40 s so far");
  CHECK(durationText(59.4) == "59 s");
  CHECK(durationText(185) == "3 min 05 s");
  CHECK(durationText(7620) == "2 h 07 min");
  CHECK(durationText(-1) == "0 s");
}

TEST_CASE("a sweep into a log names every phase and prints a whole line with rate and time left every few seconds") {
  const fs::path dir = test::scratch("progress-log");
  const auto started = std::chrono::steady_clock::now();
  const auto r = test::runCli(slowSweep(dir));  // stdout and stderr into a pipe, not a terminal
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  INFO(r.output << "(" << seconds << " s)");
  REQUIRE(r.exit_code == 0);
  REQUIRE(seconds > 10);  // the case is about long work
  CHECK(r.output.find('\r') == std::string::npos);
  for (const char* phase : {"reading data set ", "ground truth of ", "preparing the direct engine: 24 scans for 2 grids"})
    CHECK_THAT(r.output, Contains(phase));
  // Lines while it runs: at most one every 5 s (Progress::kLogInterval) as maps finish, each with its rate and the
  // time left, for each grid in turn (durations as durationText writes them: "14 s", "2 min 05 s", "1 h 03 min").
  const std::string duration = "([0-9]+ s|[0-9]+ min [0-9]{2} s|[0-9]+ h [0-9]{2} min)";
  const std::regex running(R"(sweep (knn|octomap)-opt on [^:]+ \(direct\): \d+/\d+ maps \([0-9.]+ %\), [0-9.]+ maps/s, )" +
                           duration + " left, " + duration + " so far\n");
  const auto lines = std::distance(std::sregex_iterator(r.output.begin(), r.output.end(), running), {});
  CHECK(lines >= long(seconds / 5.0) - 4);  // each grid's first 5 s, and its end, print no running line
  CHECK(lines >= 1);
  CHECK_THAT(r.output, Contains("450/450 maps (100.0 %)"));
}

TEST_CASE("on a terminal narrower than the progress line, each redraw is cut to its width, and the final line is whole") {
  // Old binary: a line of about 120 characters redrawn with \r on a 60-column terminal wrapped, and every redraw left
  // a line behind.
  if (test::runShell("command -v script").exit_code != 0) {
    WARN("no script(1): no terminal to draw on");
    return;
  }
  const fs::path dir = test::processScratch("progress-narrow");
  const std::string sweep = test::shellQuoted(test::cliUnderTest()) + " sweep --dataset " + defaultScene().string() +
                            " --grid knn-opt --shard 0/8 --engine direct --threads 1 --out " +
                            (dir / "knn.json").string();
  // script(1) runs the sweep on a pseudo-terminal of 60 columns and copies what it drew to the log. An eighth of the
  // grid: a terminal is redrawn every 200 ms, so a couple of seconds in Release draw a dozen lines (the whole grid
  // took 136 s under the sanitizers).
  const auto r = test::runShell("script -qfec " + test::shellQuoted("stty cols 60; " + sweep) + " /dev/null > " +
                                test::shellQuoted(dir / "tty.log") + " 2>&1");
  REQUIRE(r.exit_code == 0);
  std::string drawn = test::bytesOf(dir / "tty.log");
  for (std::size_t at = drawn.find("\033[K"); at != std::string::npos; at = drawn.find("\033[K")) drawn.erase(at, 3);
  for (std::size_t at = drawn.find("\r\n"); at != std::string::npos; at = drawn.find("\r\n")) drawn.erase(at, 1);  // pty's line end
  std::vector<std::string> redraws;  // what each \r began, up to the next \r or line end
  std::string final_line;
  for (std::size_t at = drawn.find('\r'); at != std::string::npos; at = drawn.find('\r', at + 1)) {
    const std::size_t end = drawn.find_first_of("\r\n", at + 1);
    const std::string part = drawn.substr(at + 1, end == std::string::npos ? std::string::npos : end - at - 1);
    if (part.starts_with("[")) (end != std::string::npos && drawn[end] == '\n' ? final_line : redraws.emplace_back()) = part;
  }
  INFO(drawn);
  REQUIRE(redraws.size() >= 2);
  for (const std::string& line : redraws) CHECK(line.size() <= 59);
  CHECK(final_line.find("in all") != std::string::npos);  // the last line whole, however wide
}

TEST_CASE("an interrupted sweep says what it kept and the command that resumes it, and that command finishes it") {
  const fs::path dir = test::scratch("progress-interrupt");
  const std::string args = slowSweep(dir);
  const std::string log = interruptedSweepLog(args, dir / "log");
  INFO(log);
  CHECK_THAT(log, Contains("occsweep sweep: interrupted; the maps it finished are kept beside each output"));
  const std::string resume = resumeLine(log);
  CHECK_THAT(resume, Catch::EndsWith(" && " + test::cliUnderTest() + " " + args));
  CHECK(fs::exists(dir / "knn.json.partial.jsonl"));

  // Run from another folder, as pasted into another terminal: it resumes all the same.
  const auto again = test::runShell("cd / && " + resume + " 2>&1");
  INFO(again.output);
  REQUIRE(again.exit_code == 0);
  CHECK_THAT(again.output, Contains("resuming "));
  for (const char* out : {"knn.json", "oct.json"})
    CHECK(test::runCli("results check " + (dir / out).string()).exit_code == 0);
}

TEST_CASE("a sweep ended by SIGTERM (a batch system's stop) says what it kept and the command that resumes it") {
  const fs::path dir = test::scratch("progress-sigterm");
  const std::string args = slowSweep(dir);
  const std::string log = interruptedSweepLog(args, dir / "log", SIGTERM);
  INFO(log);
  CHECK_THAT(log, Contains("occsweep sweep: interrupted; the maps it finished are kept beside each output"));
  CHECK_THAT(resumeLine(log), Catch::EndsWith(" && " + test::cliUnderTest() + " " + args));
  CHECK(fs::exists(dir / "knn.json.partial.jsonl"));
}

TEST_CASE("the resume command reads back, through the shell, as the arguments the sweep was given") {
  // Oracle: the shell itself. The printed line with the binary swapped for printf gives back each argument.
  const fs::path dir = test::scratch("progress quoted 'dir' $HOME");
  const std::vector<std::string> args = {"sweep", "--dataset", defaultScene().string(), "--grid", "knn-opt",
                                         "--engine", "direct", "--threads", "1", "--out",
                                         (dir / "k n \"$(x)\" `y` \\z.json").string()};
  std::string typed;
  for (const std::string& a : args) {
    typed += ' ';  // appended piece by piece: " " + std::string trips GCC 12's -Wrestrict false positive
    typed += test::shellQuoted(a);
  }
  const std::string log = interruptedSweepLog(typed.substr(1), dir / "log");
  INFO(log);
  std::string line = resumeLine(log);
  const std::string binary = " && " + test::cliUnderTest() + " ";
  const auto at = line.find(binary);
  REQUIRE(at != std::string::npos);
  line.replace(at, binary.size(), " && printf '%s\\n' ");
  std::string expected;
  for (const std::string& a : args) expected += a + "\n";
  CHECK(test::runShell(line).output == expected);
}
