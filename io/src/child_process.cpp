// Child processes that die with occsweep (docs/io.md, "Child processes").
#include "occsweep/io/child_process.hpp"

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <spawn.h>
#include <csignal>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include "occsweep/io/temporaries.hpp"

extern char** environ;

namespace occsweep {
namespace {

void writeError(const char* what, const char* detail) {
  (void)!::write(STDERR_FILENO, what, std::strlen(what));
  (void)!::write(STDERR_FILENO, detail, std::strlen(detail));
  (void)!::write(STDERR_FILENO, "\n", 1);
}

// In the child, between fork and exec: only system calls (the parent may have threads). Paths are c_str()s taken
// before the fork.
[[noreturn]] void execChild(char* const* args, pid_t parent, const sigset_t& previous_mask, const char* cwd,
                            const char* log, bool ignore_interrupt) {
  // SIGTERM when the parent dies, however it dies; it may have died before the prctl.
  if (::prctl(PR_SET_PDEATHSIG, SIGTERM) != 0 || ::getppid() != parent) ::_exit(143);
  // The parent's handlers would run here and only pass a signal on: reset them (exec would anyway), keeping what
  // is ignored (nohup). A stop signal that arrived since the fork then takes its default action when unblocked.
  if (ignore_interrupt) ::signal(SIGINT, SIG_IGN);
  for (int sig : {SIGTERM, SIGINT, SIGHUP}) {
    struct sigaction current {};
    if (::sigaction(sig, nullptr, &current) == 0 && current.sa_handler != SIG_IGN) ::signal(sig, SIG_DFL);
  }
  ::signal(SIGPIPE, SIG_DFL);  // occsweep ignores it for itself (main.cpp); a child gets the usual behaviour
  ::sigprocmask(SIG_SETMASK, &previous_mask, nullptr);
  if (*log) {
    const int out = ::open(log, O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC | O_NOFOLLOW, 0644);
    const int in = ::open("/dev/null", O_RDONLY | O_CLOEXEC);
    if (out < 0 || in < 0 || ::dup2(out, STDOUT_FILENO) < 0 || ::dup2(out, STDERR_FILENO) < 0 ||
        ::dup2(in, STDIN_FILENO) < 0)
      ::_exit(127);
  }
  if (*cwd && ::chdir(cwd) != 0) {
    writeError("occsweep: cannot enter the folder to run in: ", std::strerror(errno));
    ::_exit(127);
  }
  ::execvp(args[0], args);
  writeError("occsweep: cannot start the program: ", std::strerror(errno));
  ::_exit(127);
}

}  // namespace

pid_t startChild(const std::vector<std::string>& argv, const ChildSetup& setup) {
  auto args = execArgv(argv);  // built before fork: the child only makes system calls
  const std::string cwd = setup.cwd.string(), log = setup.log.string();
  const pid_t parent = ::getpid();
  sigset_t stop_signals, previous;
  sigemptyset(&stop_signals);
  for (int sig : {SIGTERM, SIGINT, SIGHUP}) sigaddset(&stop_signals, sig);
  ::pthread_sigmask(SIG_BLOCK, &stop_signals, &previous);
  const pid_t pid = setup.registered ? forkRegisteredChild() : ::fork();
  if (pid == 0) execChild(args.data(), parent, previous, cwd.c_str(), log.c_str(), setup.ignore_interrupt);
  ::pthread_sigmask(SIG_SETMASK, &previous, nullptr);  // a signal meanwhile runs the handler now
  return pid < 0 ? -1 : pid;
}

std::vector<char*> execArgv(const std::vector<std::string>& argv) {
  std::vector<char*> out;
  for (const auto& a : argv) out.push_back(const_cast<char*>(a.c_str()));
  out.push_back(nullptr);
  return out;
}

std::string shellWord(const std::string& arg) {
  if (!arg.empty() && arg.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-./=:,+@%") ==
                          std::string::npos)
    return arg;
  std::string quoted = "'";
  for (char c : arg) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

int exitCodeOf(int status) {
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return -1;
}

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

int runChild(const std::vector<std::string>& argv) {
  ChildSetup setup;
  setup.ignore_interrupt = true, setup.registered = true;
  const pid_t pid = startChild(argv, setup);
  if (pid < 0) return 127;
  // Waited for without reaping, forgotten, then reaped: the interrupt handler never kills a PID reused meanwhile.
  siginfo_t info{};
  while (::waitid(P_PID, id_t(pid), &info, WEXITED | WNOWAIT) < 0 && errno == EINTR) {
  }
  unregisterChildProcess(pid);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  return exitCodeOf(status);
}

}  // namespace occsweep
