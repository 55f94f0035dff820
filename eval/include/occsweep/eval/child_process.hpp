// A program occsweep runs and waits for (the figure scripts of `plot` and `reproduce`): it never outlives occsweep
// (docs/robustness.md, "Child processes").
#pragma once

#include <string>
#include <vector>

namespace occsweep {

/// Runs argv (searched on PATH, no shell) with this process's stdin, stdout and stderr, and waits. Returns its exit
/// code, 128 + signal when a signal ended it, 127 when it cannot be started. The child gets SIGTERM when occsweep
/// dies, even by SIGKILL (PR_SET_PDEATHSIG); on SIGINT, SIGTERM or SIGHUP occsweep's interrupt handler kills it
/// and waits for it before removing the temporaries it was writing (removeTemporariesOnInterrupt). It ignores
/// SIGINT: a Ctrl-C reaches occsweep, which ends it, instead of a Python traceback.
[[nodiscard]] int runChild(const std::vector<std::string>& argv);

/// argv as exec wants it: pointers into `argv`'s strings, then nullptr. Built before fork (the child of a threaded
/// process may only make system calls).
[[nodiscard]] std::vector<char*> execArgv(const std::vector<std::string>& argv);

/// A finished child's exit code from its wait status: its own, 128 + signal when a signal ended it, else -1.
[[nodiscard]] int exitCodeOf(int wait_status);

}  // namespace occsweep
