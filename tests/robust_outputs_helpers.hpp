// Helpers of the output tests (test_robust_outputs, test_robust_ownership, test_robust_faults, test_robust_disk):
// running the command in a folder, killing it once its partial log holds some maps, snapshots of folders to show files
// byte-identical, and the search for leftover temporaries.
#pragma once

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <sys/wait.h>

#include "test_helpers.hpp"

namespace occsweep::test {

inline std::string fileBytes(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

inline void writeBytes(const std::filesystem::path& file, const std::string& bytes) {
  std::ofstream(file, std::ios::binary) << bytes;
}

/// Every file under `dir` (relative path -> bytes): two equal snapshots mean nothing was changed, added or removed.
inline std::map<std::string, std::string> snapshot(const std::filesystem::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir))
    files[std::filesystem::relative(e.path(), dir).string()] = e.is_regular_file() ? fileBytes(e.path()) : "<dir>";
  return files;
}

/// Temporaries anywhere under `dir`: names holding ".tmp-" or ".old-" (both ever used by occsweep).
inline std::vector<std::string> leftovers(const std::filesystem::path& dir) {
  std::vector<std::string> found;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (name.find(".tmp-") != std::string::npos || name.find(".old-") != std::string::npos || name.ends_with(".tmp"))
      found.push_back(e.path().string());
  }
  return found;
}

/// The tiny OctoMap grid the output tests sweep: three p_h by three p_m values, swept in milliseconds.
inline void writeTinyGrid(const std::filesystem::path& file) {
  std::ofstream(file) << R"({"name": "tiny", "method": "octomap", "parameters": {"p_max": {"value": 0.98},
    "p_min": {"value": 0.02}, "p_h": {"min": 0.5, "max": 0.98, "step": 0.24},
    "p_m": {"min": 0.02, "max": 0.38, "step": 0.18}, "p_t": {"step": 0.12}}})";
}

/// A tiny scene: four scans of 16 x 12 rays (milliseconds).
inline const char* kTinyScene = "scene --scans 4 --width 16 --height 12";

/// What a kill left in a sweep's partial log: whether the command died of the signal, and the log's line breaks then.
struct KilledRun {
  bool killed = false;
  std::size_t lines = 0;
};

/// Runs `occsweep ARGS` in `dir` (its output discarded) and kills it with SIGKILL once `log` holds `lines` line
/// breaks (or after 20 s): the state a kill leaves for the next run to resume from.
inline KilledRun killOnceLogged(const std::filesystem::path& dir, const std::string& args,
                                const std::filesystem::path& log, std::size_t lines) {
  const pid_t pid = occsweep::test::startShell("cd " + occsweep::test::shellQuoted(dir) + " && exec " +
                                               occsweep::test::shellQuoted(occsweep::test::cliUnderTest()) + " " +
                                               args + " > /dev/null 2>&1");
  auto logged = [&] {
    const std::string text = fileBytes(log);
    return std::size_t(std::count(text.begin(), text.end(), '\n'));
  };
  for (int i = 0; i < 20000 && logged() < lines; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  ::kill(pid, SIGKILL);
  int status = 0;
  ::waitpid(pid, &status, 0);
  return {WIFSIGNALED(status), logged()};
}

}  // namespace occsweep::test
