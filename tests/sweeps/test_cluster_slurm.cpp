// `occsweep cluster` on a real one-node Slurm (tests/cluster/slurm_e2e.sh, which installs Slurm when missing, starts
// it and always stops it), then the merged results of Slurm, of the Slurm run after a failed task was resubmitted,
// and of run-local compared number for number.
#include <catch2/catch.hpp>

#include <cstdlib>
#include <sys/wait.h>
#include <unistd.h>

#include "occsweep/sweeps/results.hpp"
#include "test_helpers.hpp"

using namespace occsweep;
namespace fs = std::filesystem;

TEST_CASE("a plan run by Slurm with one task failed and resubmitted merges to exactly run-local's results") {
  if (::geteuid() != 0) FAIL("the one-node Slurm test runs as root (it installs Slurm and runs its daemons)");
  const fs::path work = test::scratch("cluster-slurm");
  const std::string script = occsweep::test::sourceTree().string() + "/tests/cluster/slurm_e2e.sh";
  const std::string cmd = "bash '" + script + "' '" + occsweep::test::builtCli() + "' '" + (work / "run").string() + "' > '" +
                          (work / "e2e.log").string() + "' 2>&1";
  const int status = std::system(cmd.c_str());
  const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  if (code != 0) {
    std::ifstream in(work / "e2e.log");
    const std::string log((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    FAIL("slurm_e2e.sh exited " << code << ":\n" << log.substr(log.size() > 6000 ? log.size() - 6000 : 0));
  }
  const fs::path local = work / "run" / "local" / "merged";
  std::size_t compared = 0;
  for (const auto& entry : fs::recursive_directory_iterator(local)) {
    if (!entry.is_regular_file() || entry.path().extension() != ".json") continue;
    const fs::path rel = fs::relative(entry.path(), local);
    const ResultsFile expected = readResults(entry.path());
    REQUIRE(expected.complete);
    for (const fs::path& other : {work / "run" / "first-merged" / rel, work / "run" / "slurm" / "merged" / rel}) {
      INFO(other.string());
      const auto diff = resultDifferences(expected, readResults(other));
      CHECK(diff.empty());
      ++compared;
    }
  }
  CHECK(compared == 2 * 6);  // 2 data sets x 3 grids, each against the first Slurm run and the resubmitted one
}
