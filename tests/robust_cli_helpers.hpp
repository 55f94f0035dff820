// Helpers of the "Messages, formats and the cluster" tests (docs/robustness.md); the occsweep under test and
// commands run in a folder are test_helpers.hpp's (OCCSWEEP_TEST_CLI points at another build).
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
