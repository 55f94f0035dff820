// Child processes, started without a shell: Slurm's clients (captured) and run-local's tasks (logged, ending with
// run-local). Figure scripts run through eval's runChild (child_process.hpp).
#include <cerrno>
#include <cstring>
#include <csignal>
#include <fcntl.h>
#include <spawn.h>
#include <stdexcept>
#include <sys/prctl.h>
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
  auto args = execArgv(argv);  // built before fork: the child only makes system calls
  const pid_t parent = ::getpid();
  // The stop signals are blocked across fork: the child inherits run-local's handler, which, run in the child,
  // would only pass the signal on and leave the task running (a survivor, docs/cluster.md "Stopping run-local").
  // Blocked, a signal waits in the child until its handlers are reset below, then ends it.
  sigset_t stop_signals, previous;
  sigemptyset(&stop_signals);
  for (int signal : {SIGTERM, SIGINT, SIGHUP}) sigaddset(&stop_signals, signal);
  ::pthread_sigmask(SIG_BLOCK, &stop_signals, &previous);
  const pid_t pid = ::fork();
  if (pid != 0) {
    const int fork_error = errno;
    ::pthread_sigmask(SIG_SETMASK, &previous, nullptr);  // a signal meanwhile runs the handler now
    if (pid < 0) throw std::runtime_error("cannot start " + argv[0] + ": fork: " + std::strerror(fork_error));
    return pid;
  }
  // The child. SIGTERM when the parent dies, however it dies; it may have died before the prctl.
  if (::prctl(PR_SET_PDEATHSIG, SIGTERM) != 0 || ::getppid() != parent) ::_exit(143);
  // Caught signals are reset by exec anyway: reset them now, so run-local's handler never runs in the child;
  // ignored ones (nohup) stay ignored. Then a pending stop signal takes its default action: the child ends.
  for (int signal : {SIGTERM, SIGINT, SIGHUP}) {
    struct sigaction current {};
    if (::sigaction(signal, nullptr, &current) == 0 && current.sa_handler != SIG_IGN) ::signal(signal, SIG_DFL);
  }
  ::sigprocmask(SIG_SETMASK, &previous, nullptr);
  const int out = ::open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  const int in = ::open("/dev/null", O_RDONLY | O_CLOEXEC);
  if (out < 0 || in < 0 || ::dup2(out, STDOUT_FILENO) < 0 || ::dup2(out, STDERR_FILENO) < 0 ||
      ::dup2(in, STDIN_FILENO) < 0)
    ::_exit(127);
  if (::chdir(cwd.c_str()) != 0) {
    const char* why = "run-local: cannot enter the plan folder\n";
    (void)!::write(STDERR_FILENO, why, std::strlen(why));
    ::_exit(127);
  }
  ::execvp(args[0], args.data());
  const char* why = "run-local: cannot start the task's program: ";
  (void)!::write(STDERR_FILENO, why, std::strlen(why));
  (void)!::write(STDERR_FILENO, std::strerror(errno), std::strlen(std::strerror(errno)));
  (void)!::write(STDERR_FILENO, "\n", 1);
  ::_exit(127);
}

}  // namespace occsweep
