// Where a test program finds its build tree, the source tree and the built command. They are read at run time, not
// compiled in: with no absolute path in a test's object, the compiler cache reuses it from any clone of the same
// sources (docs/robustness.md, "CI's time").
#pragma once

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

namespace occsweep::test {

/// The build tree: the nearest folder above this program that holds CMakeCache.txt (every test program is built
/// under it; /proc/self/exe names the program whatever the current folder).
inline const std::filesystem::path& buildTree() {
  static const std::filesystem::path tree = [] {
    const auto program = std::filesystem::read_symlink("/proc/self/exe");
    for (auto dir = program.parent_path(); dir != dir.root_path(); dir = dir.parent_path())
      if (std::filesystem::exists(dir / "CMakeCache.txt")) return dir;
    throw std::runtime_error(program.string() + ": not inside a CMake build tree (no CMakeCache.txt above it)");
  }();
  return tree;
}

/// The source tree the build tree was configured from: CMakeCache.txt's CMAKE_HOME_DIRECTORY.
inline const std::filesystem::path& sourceTree() {
  static const std::filesystem::path tree = [] {
    const std::string key = "CMAKE_HOME_DIRECTORY:INTERNAL=";
    std::ifstream cache(buildTree() / "CMakeCache.txt");
    for (std::string line; std::getline(cache, line);)
      if (line.rfind(key, 0) == 0) return std::filesystem::path(line.substr(key.size()));
    throw std::runtime_error((buildTree() / "CMakeCache.txt").string() + ": no CMAKE_HOME_DIRECTORY");
  }();
  return tree;
}

/// This build's occsweep command (the `occsweep` target of tools/).
inline std::string builtCli() { return (buildTree() / "tools" / "occsweep").string(); }

}  // namespace occsweep::test
