// A program occsweep runs and waits for (the figure scripts of `plot` and `reproduce`): it never outlives occsweep
// (docs/io.md, "Child processes").
#pragma once

#include <filesystem>
#include <string>
#include <sys/types.h>
#include <vector>

namespace occsweep {

/// Runs argv (searched on PATH, no shell) with this process's stdin, stdout and stderr, and waits. Returns its exit
/// code, 128 + signal when a signal ended it, 127 when it cannot be started. The child gets SIGTERM when occsweep
/// dies, even by SIGKILL (PR_SET_PDEATHSIG); on SIGINT, SIGTERM or SIGHUP occsweep's interrupt handler kills it
/// and waits for it before removing the temporaries it was writing (removeTemporariesOnInterrupt). It ignores
/// SIGINT: a Ctrl-C reaches occsweep, which ends it, instead of a Python traceback.
[[nodiscard]] int runChild(const std::vector<std::string>& argv);

/// How a started child is set up between fork and exec (startChild).
struct ChildSetup {
  std::filesystem::path cwd;  ///< entered before exec; empty: this process's folder
  std::filesystem::path log;  ///< stdout and stderr appended here, stdin from /dev/null; empty: this process's
  bool ignore_interrupt = false;  ///< SIGINT ignored: occsweep, which the Ctrl-C reaches, ends the child itself
  bool registered = false;        ///< forked under the interrupt registry (killed and waited for on SIGINT/SIGTERM)
};

/// The one way occsweep starts a program (no shell, PATH searched): stop signals blocked across the fork, then in
/// the child SIGTERM when occsweep dies however it dies (PR_SET_PDEATHSIG), its stop-signal handlers reset to their
/// defaults (ignored ones stay ignored), `setup` applied, and exec. A failure after the fork is written to the
/// child's stderr and ends it with 127. Returns its PID; -1 when it was not started (fork failed, or an interrupt
/// arrived first for a registered child). docs/io.md, "Child processes".
[[nodiscard]] pid_t startChild(const std::vector<std::string>& argv, const ChildSetup& setup);

/// argv as exec wants it: pointers into `argv`'s strings, then nullptr. Built before fork (the child of a threaded
/// process may only make system calls).
[[nodiscard]] std::vector<char*> execArgv(const std::vector<std::string>& argv);

/// What runCapture read of a program.
struct ProcessOutput {
  int exit_code = -1;  ///< 127 when the program is not found, 128 + signal when killed
  std::string text;    ///< stdout
};
/// Runs argv (searched on PATH, no shell) and captures its stdout; stderr passes through, or goes to /dev/null when
/// `quiet` (Slurm's status queries: sacct without accounting complains on every call; a Python probe). For short
/// queries only: the child is not registered with the interrupt handler.
[[nodiscard]] ProcessOutput runCapture(const std::vector<std::string>& argv, bool quiet = false);

/// One argument as a shell reads it back: as it is when it holds only plain characters (letters, digits, _-./=:,+@%),
/// otherwise in single quotes (a quote inside as '\''). For the command lines occsweep prints or writes into scripts.
[[nodiscard]] std::string shellWord(const std::string& arg);

/// A finished child's exit code from its wait status: its own, 128 + signal when a signal ended it, else -1.
[[nodiscard]] int exitCodeOf(int wait_status);

}  // namespace occsweep
