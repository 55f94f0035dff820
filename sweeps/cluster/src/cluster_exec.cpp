// Child processes, started without a shell: Slurm's clients (captured) and run-local's tasks (logged, ending with
// run-local). Figure scripts run through eval's runChild (child_process.hpp).
#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <spawn.h>
#include <stdexcept>
#include <sys/wait.h>
#include <unistd.h>

#include "occsweep/eval/child_process.hpp"
#include "occsweep/sweeps/cluster_state.hpp"

extern char** environ;

namespace occsweep {
namespace {

int waitForExit(pid_t pid) {
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  return exitCodeOf(status);
}

}  // namespace

ProcessOutput runCapture(const std::vector<std::string>& argv, bool quiet) {
  int fds[2];
  if (::pipe(fds) != 0) throw std::runtime_error(std::string("pipe: ") + std::strerror(errno));
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, fds[1], STDOUT_FILENO);
  posix_spawn_file_actions_addclose(&actions, fds[0]);
  posix_spawn_file_actions_addclose(&actions, fds[1]);
  if (quiet) posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
  pid_t pid = 0;
  auto args = execArgv(argv);
  const int rc = posix_spawnp(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(fds[1]);
  ProcessOutput out;
  if (rc != 0) {
    ::close(fds[0]);
    out.exit_code = 127;
    return out;
  }
  char buf[4096];
  for (;;) {
    const ssize_t n = ::read(fds[0], buf, sizeof buf);
    if (n > 0) out.text.append(buf, std::size_t(n));
    else if (n == 0 || errno != EINTR) break;
  }
  ::close(fds[0]);
  out.exit_code = waitForExit(pid);
  return out;
}

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
