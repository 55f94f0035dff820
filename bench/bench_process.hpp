// What the benchmarks measure of an occsweep process as a user runs it: its wall time and peak resident memory.
#pragma once

#include <chrono>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "test_paths.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

namespace occsweep::bench {

/// Where a benchmark writes its scratch data: the build tree's bench/ folder.
inline std::filesystem::path scratchDir() { return test::buildTree() / "bench"; }

/// The build tree's copy of the shipped grids (docs/install.md).
inline std::filesystem::path builtGrids() { return test::buildTree() / OCCSWEEP_SHARE_SUBDIR / "grids"; }

struct ProcessRun {
  double seconds = 0.0;
  double peak_bytes = 0.0;  ///< VmHWM
};

template <class Fn>
double seconds(Fn&& fn) {
  const auto t0 = std::chrono::steady_clock::now();
  fn();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// Runs `occsweep ARGS` to its end, its stdout to /dev/null, polling its VmHWM. posix_spawn, not fork: a forked
/// child's VmHWM counts this large process's pages until it execs, and polling could read that; posix_spawn
/// returns only once the child runs the new program. Throws when it fails.
inline ProcessRun runOccsweep(const std::vector<std::string>& args) {
  const std::string cli = test::builtCli();
  std::vector<char*> argv{const_cast<char*>(cli.c_str())};
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t quiet;
  posix_spawn_file_actions_init(&quiet);
  posix_spawn_file_actions_addopen(&quiet, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  const auto t0 = std::chrono::steady_clock::now();
  pid_t child = 0;
  const int failed = ::posix_spawn(&child, cli.c_str(), &quiet, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&quiet);
  if (failed) throw std::runtime_error("cannot start occsweep");
  ProcessRun run;
  const std::string status_file = "/proc/" + std::to_string(child) + "/status";
  int status = 0;
  while (::waitpid(child, &status, WNOHANG) == 0) {
    std::ifstream in(status_file);
    for (std::string line; std::getline(in, line);)
      if (line.rfind("VmHWM:", 0) == 0) run.peak_bytes = std::max(run.peak_bytes, std::stod(line.substr(6)) * 1024.0);
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) throw std::runtime_error("occsweep " + args[0] + " failed");
  return run;
}

}  // namespace occsweep::bench
