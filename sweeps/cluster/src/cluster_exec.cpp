// run-local's tasks, started without a shell, logged, ending with run-local (docs/cluster.md). Slurm's clients run
// through eval's runCapture and figure scripts through its runChild (child_process.hpp).
#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "occsweep/io/child_process.hpp"
#include "occsweep/sweeps/cluster_state.hpp"

namespace occsweep {

pid_t spawnLogged(const std::vector<std::string>& argv, const std::filesystem::path& cwd,
                  const std::filesystem::path& log) {
  // Not registered: run-local's own handler ends its tasks (docs/cluster.md, "Stopping run-local").
  ChildSetup setup;
  setup.cwd = cwd, setup.log = log;
  const pid_t pid = startChild(argv, setup);
  if (pid < 0) throw std::runtime_error("cannot start " + argv[0] + ": fork: " + std::strerror(errno));
  return pid;
}

}  // namespace occsweep
