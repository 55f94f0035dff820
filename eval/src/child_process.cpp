// Child processes that die with occsweep (docs/robustness.md, "Child processes").
#include "occsweep/eval/child_process.hpp"

#include <cerrno>
#include <csignal>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include "occsweep/eval/output_file.hpp"

namespace occsweep {
namespace {

// In the child, between fork and exec: only system calls.
[[noreturn]] void execChild(char* const* args, pid_t parent, const sigset_t& previous_mask) {
  // SIGTERM when the parent dies, however it dies; it may have died before the prctl.
  if (::prctl(PR_SET_PDEATHSIG, SIGTERM) != 0 || ::getppid() != parent) ::_exit(143);
  ::signal(SIGINT, SIG_IGN);  // occsweep ends it on a Ctrl-C (a Python child would print a traceback)
  for (int sig : {SIGTERM, SIGHUP}) {
    struct sigaction current {};
    if (::sigaction(sig, nullptr, &current) == 0 && current.sa_handler != SIG_IGN) ::signal(sig, SIG_DFL);
  }
  ::sigprocmask(SIG_SETMASK, &previous_mask, nullptr);
  ::execvp(args[0], args);
  ::_exit(127);
}

}  // namespace

std::vector<char*> execArgv(const std::vector<std::string>& argv) {
  std::vector<char*> out;
  for (const auto& a : argv) out.push_back(const_cast<char*>(a.c_str()));
  out.push_back(nullptr);
  return out;
}

int exitCodeOf(int status) {
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return -1;
}

int runChild(const std::vector<std::string>& argv) {
  auto args = execArgv(argv);  // built before fork: the child only makes system calls
  const pid_t parent = ::getpid();
  // Stop signals blocked across fork in this thread: the child resets its handlers before it may receive one.
  sigset_t stop_signals, previous;
  sigemptyset(&stop_signals);
  for (int sig : {SIGTERM, SIGINT, SIGHUP}) sigaddset(&stop_signals, sig);
  ::pthread_sigmask(SIG_BLOCK, &stop_signals, &previous);
  const pid_t pid = forkRegisteredChild();
  if (pid == 0) execChild(args.data(), parent, previous);
  ::pthread_sigmask(SIG_SETMASK, &previous, nullptr);
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
