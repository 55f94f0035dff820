// Where the command finds its grids (docs/install.md): $OCCSWEEP_GRIDS first, then share/occsweep/grids beside its
// own folder, and no path of the source tree compiled in. The install test (tools/ci/install_test.sh) runs the
// installed command with the source tree's grids moved away; these run the built one.
#include <catch2/catch.hpp>

#include <fstream>

#include "test_helpers.hpp"

namespace fs = std::filesystem;
using namespace occsweep::test;

namespace {

/// The built command with `env` in front of it (e.g. "env -u OCCSWEEP_GRIDS"), run from an empty folder.
CommandResult runWithEnvironment(const std::string& env, const std::string& args) {
  const fs::path elsewhere = processScratch("install_paths_cwd");
  return runShell("cd " + shellQuoted(elsewhere) + " && " + env + " " + shellQuoted(cliUnderTest()) + " " + args +
                  " 2>&1");
}

}  // namespace

TEST_CASE("without OCCSWEEP_GRIDS the command finds its grids beside itself, from any folder") {
  const CommandResult r = runWithEnvironment("env -u OCCSWEEP_GRIDS", "grid count knn-opt");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK(r.output.find("knn-opt: 4050 combinations") != std::string::npos);
}

TEST_CASE("a grid of OCCSWEEP_GRIDS wins over the shipped grid of the same name") {
  const fs::path mine = processScratch("install_paths_grids");
  std::ifstream shipped(occsweep::test::sourceTree() / "sweeps" / "grids" / "octomap-opt.json");
  std::ofstream(mine / "knn-opt.json") << shipped.rdbuf();  // an OctoMap grid under the k-NN grid's name
  const CommandResult r = runWithEnvironment("OCCSWEEP_GRIDS=" + shellQuoted(mine), "grid count knn-opt");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK(r.output.find(": 180 combinations") != std::string::npos);  // the grid names itself octomap-opt
}

TEST_CASE("an unknown grid name is refused naming every folder searched") {
  const fs::path empty = processScratch("install_paths_empty");
  const CommandResult r = runWithEnvironment("OCCSWEEP_GRIDS=" + shellQuoted(empty), "grid count no-such-grid");
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK(r.output.find(empty.string()) != std::string::npos);
  CHECK(r.output.find("share/occsweep/grids") != std::string::npos);
}

TEST_CASE("the command carries no path of the source tree") {
  // A compiled-in source folder shows up in the binary as a string of its own, ending right after the folder's name
  // (the old OCCSWEEP_SOURCE_DIR did). File names that assertions keep (OpenCV's CV_Assert holds __FILE__) go on
  // past it, "FOLDER/tools/...", and are no such string. A build with debug information names its source folder
  // in its own right, so there the check cannot tell and says so.
  const std::string binary = bytesOf(cliUnderTest());
  REQUIRE(!binary.empty());
  if (binary.find(".debug_info") != std::string::npos) {
    WARN("the command has debug information (which names the source files): not checked in this build");
    return;
  }
  CHECK(binary.find(occsweep::test::sourceTree().string() + '\0') == std::string::npos);
}
