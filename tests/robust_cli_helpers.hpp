// Helpers of the "Messages, formats and the cluster" tests (docs/robustness.md): the occsweep under test, which
// OCCSWEEP_UNDER_TEST can point at another build (to see a test fail on the code before a fix), and commands run
// in a given folder.
#pragma once

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <sys/wait.h>
#include <vector>

#include "test_helpers.hpp"

namespace occsweep::test {

/// The occsweep binary the robustness tests run: $OCCSWEEP_UNDER_TEST, else this build's.
inline std::string cliUnderTest() {
  const char* other = std::getenv("OCCSWEEP_UNDER_TEST");
  return other && *other ? std::string(other) : std::string(OCCSWEEP_CLI);
}

/// Runs `occsweep ARGS` (a shell string) in `cwd`, stdout and stderr together.
inline CommandResult runIn(const std::filesystem::path& cwd, const std::string& args) {
  const std::string cmd = "cd '" + cwd.string() + "' && " + cliUnderTest() + " " + args + " 2>&1";
  CommandResult r;
  FILE* pipe = ::popen(cmd.c_str(), "r");
  if (!pipe) return r;
  char buf[4096];
  while (std::size_t n = std::fread(buf, 1, sizeof buf, pipe)) r.output.append(buf, n);
  const int status = ::pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

inline CommandResult run(const std::string& args) { return runIn(std::filesystem::current_path(), args); }

/// Every file and folder under `dir`, relative, sorted: to show that a refused command left nothing behind.
inline std::vector<std::string> listing(const std::filesystem::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir))
    out.push_back(std::filesystem::relative(e.path(), dir).string());
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace occsweep::test
