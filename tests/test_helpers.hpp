// Shared helpers of the test programs: random clouds, temporary folders, running the occsweep command.
#pragma once

#include <algorithm>
#include <csignal>
#include <pthread.h>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

#include <octomap/octomap_types.h>

#include "occsweep/core/splitmix64.hpp"
#include "test_paths.hpp"

namespace occsweep::test {

/// The bytes of a file ("" when it cannot be read).
inline std::string bytesOf(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Relative paths of every regular file under `dir`, sorted, except timing.json (wall-clock times): what two
/// generations that must be byte-identical are compared over.
inline std::vector<std::filesystem::path> filesUnder(const std::filesystem::path& dir) {
  std::vector<std::filesystem::path> out;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir))
    if (e.is_regular_file() && e.path().filename() != "timing.json") out.push_back(std::filesystem::relative(e.path(), dir));
  std::sort(out.begin(), out.end());
  return out;
}

/// `text` with every line break and the indentation after it removed: a path or name that `occsweep compare` cut
/// at the ends of its 100-column lines reads whole again (docs/statistics.md, "In occsweep compare"), wherever the
/// build tree, and so the test's folder, lies.
inline std::string joinedLines(const std::string& text) {
  std::string out;
  for (std::size_t at = 0; at < text.size(); ++at) {
    if (text[at] != '\n') {
      out += text[at];
      continue;
    }
    while (at + 1 < text.size() && text[at + 1] == ' ') ++at;
  }
  return out;
}

/// A fresh folder under the build tree, removed first if it exists.
inline std::filesystem::path scratch(const std::string& name) {
  const auto dir = occsweep::test::buildTree() / "test-scratch" / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

/// scratch(name) of this process alone: ctest runs each test case as its own process, two at a time, so a folder
/// shared by a program's cases (a scene written once) must not be shared between processes.
inline std::filesystem::path processScratch(const std::string& name) {
  return scratch(name + "-pid" + std::to_string(::getpid()));
}

inline std::vector<octomap::point3d> randomCloud(SplitMix64& rng, std::size_t n, double extent) {
  std::vector<octomap::point3d> pts;
  for (std::size_t i = 0; i < n; ++i)
    pts.emplace_back(float((rng.uniform() - 0.5) * extent), float((rng.uniform() - 0.5) * extent),
                     float((rng.uniform() - 0.5) * extent));
  return pts;
}

struct CommandResult {
  int exit_code = -1;
  std::string output;  ///< stdout and stderr together
};

/// The occsweep binary the tests run: $OCCSWEEP_TEST_CLI when set (e.g. the build before a fix, to see a test fail
/// on it), else this build's.
inline std::string cliUnderTest() {
  const char* other = std::getenv("OCCSWEEP_TEST_CLI");
  return other && *other ? std::string(other) : occsweep::test::builtCli();
}

/// `p` in single quotes for the shell.
inline std::string shellQuoted(const std::filesystem::path& p) {
  std::string q = "'";
  for (char c : p.string()) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

/// Runs a shell command line and captures what it prints.
inline CommandResult runShell(const std::string& cmd) {
  CommandResult r;
  FILE* pipe = ::popen(cmd.c_str(), "r");
  if (!pipe) return r;
  char buf[4096];
  while (std::size_t n = std::fread(buf, 1, sizeof buf, pipe)) r.output.append(buf, n);
  const int status = ::pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

/// Runs the occsweep binary with arguments (a shell string), stdout and stderr together.
inline CommandResult runCli(const std::string& args) {
  return runShell(shellQuoted(cliUnderTest()) + " " + args + " 2>&1");
}

/// Forks a child that runs `exec_in_child` (which execs, or returns to _exit(127)) and returns its PID, for tests
/// that signal it. SIGINT and SIGTERM are blocked across fork and reset to their default in the child before they
/// are unblocked: a signal that arrives before exec ends the child instead of running Catch's handler there, which
/// reports a failure from the child and can deadlock on malloc's lock after a fork of a threaded process.
template <class ExecInChild>
pid_t startChildProgram(ExecInChild exec_in_child) {
  sigset_t stop, previous;
  sigemptyset(&stop);
  sigaddset(&stop, SIGINT);
  sigaddset(&stop, SIGTERM);
  ::pthread_sigmask(SIG_BLOCK, &stop, &previous);
  const pid_t child = ::fork();
  if (child == 0) {
    ::signal(SIGINT, SIG_DFL);
    ::signal(SIGTERM, SIG_DFL);
    ::sigprocmask(SIG_SETMASK, &previous, nullptr);
    exec_in_child();
    ::_exit(127);
  }
  ::pthread_sigmask(SIG_SETMASK, &previous, nullptr);
  return child;
}

/// Starts `/bin/sh -c line` as a child (startChildProgram) and returns its PID.
inline pid_t startShell(const std::string& line) {
  return startChildProgram([&] { ::execl("/bin/sh", "sh", "-c", line.c_str(), static_cast<char*>(nullptr)); });
}

/// runCli in folder `cwd`, with `prefix` first (e.g. "ulimit -f 4;").
inline CommandResult runIn(const std::filesystem::path& cwd, const std::string& args, const std::string& prefix = "") {
  return runShell("cd " + shellQuoted(cwd) + " && " + prefix + " " + shellQuoted(cliUnderTest()) + " " + args +
                  " 2>&1");
}

}  // namespace occsweep::test
