// Every leaf command's --help ends with a runnable example (docs/cli.md); this runs them all, in an order where each
// finds what earlier ones wrote, from a folder where `tests/` is the repository's (its real samples).
#include <catch2/catch.hpp>

#include <algorithm>

#include "cli_help.hpp"
#include "test_paths.hpp"

namespace fs = std::filesystem;

namespace {

// Leaves in the order their examples run: later ones read what earlier ones wrote (ds, oct.json, knn.json, gen/...).
const std::vector<std::string> kOrder = {
    "scene", "sweep", "grid count", "grid list", "grid shards", "methods", "map", "mapdiff", "merge", "compare",
    "plot curves", "plot budget", "plot improvement", "plot params", "results check", "results diff",
    "results export", "import depth", "import graph", "import cloud", "import truth", "dataset generate",
    "dataset middlebury", "cluster select", "cluster plan", "cluster run-local", "cluster status", "cluster submit",
    "cluster resubmit", "reproduce"};

// Submitting needs a running Slurm; tests/sweeps/test_cluster_slurm.cpp starts one of its own for its run.
bool slurmAnswers() { return occsweep::test::runShell("sinfo > /dev/null 2>&1 && echo up").output == "up\n"; }

}  // namespace

TEST_CASE("every leaf command's --help has an example, and every example runs") {
  std::map<std::string, occsweep::test::LeafHelp> leaves;
  occsweep::test::walkHelp("", leaves);
  std::set<std::string> ordered(kOrder.begin(), kOrder.end()), walked;
  for (const auto& [command, help] : leaves) walked.insert(command);
  REQUIRE(walked == ordered);  // a new command needs an example, and a place in kOrder
  const fs::path dir = occsweep::test::scratch("help-examples");
  fs::create_directory_symlink(occsweep::test::sourceTree() / "tests", dir / "tests");
  const bool slurm = slurmAnswers();
  for (const std::string& command : kOrder) {
    INFO(command);
    const auto& example = leaves.at(command).example;
    CHECK_FALSE(example.empty());
    if ((command == "cluster submit" || command == "cluster resubmit") && !slurm) {
      if (command == "cluster submit")
        WARN("no Slurm answers here (sinfo): cluster submit's and resubmit's examples are not run");
      continue;
    }
    for (const std::string& line : example) {
      const std::string args = line.substr(std::string("occsweep ").size());
      const auto r = occsweep::test::runShell("cd " + occsweep::test::shellQuoted(dir) + " && " +
                                              occsweep::test::shellQuoted(occsweep::test::cliUnderTest()) + " " +
                                              args + " 2>&1");
      INFO(line << "\n" << r.output);
      CHECK(r.exit_code == 0);
    }
  }
}
