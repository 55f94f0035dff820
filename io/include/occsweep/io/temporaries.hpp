// This process's temporaries: made exclusively, removed only while they are the entry this process made, on an
// error, on SIGINT, SIGTERM or SIGHUP, or by their owner; children an interrupt ends before it removes them
// (docs/io.md, "Outputs and --force").
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <sys/types.h>
#include <utility>

namespace occsweep {

/// What a RegisteredTemporary makes at its name: an empty file or an empty folder.
enum class TemporaryKind { File, Folder };

/// A temporary of `target` (ownership.hpp), made exclusively, empty, and registered in one step: removed with what
/// it holds (and an SQLite `-journal` beside it) on SIGINT, SIGTERM or SIGHUP, or when destroyed, while it is the
/// entry made there (once renamed into place, it is not). Every writer fills one and renames it into place
/// (OutputFile, OutputFolder, a sweep's partial output, a script's figures); one that opens it by its name opens it
/// without creating it: a temporary an interrupt has removed is then never made again before the exit.
class RegisteredTemporary {
 public:
  RegisteredTemporary(const std::filesystem::path& target, TemporaryKind kind);
  ~RegisteredTemporary();
  RegisteredTemporary(const RegisteredTemporary&) = delete;
  RegisteredTemporary& operator=(const RegisteredTemporary&) = delete;
  [[nodiscard]] const std::filesystem::path& path() const { return path_; }
  /// The file's descriptor, open for writing, now the caller's to close (-1 for a folder, or when taken before).
  [[nodiscard]] int takeDescriptor() { return std::exchange(fd_, -1); }
  /// Leaves what stands at path() where it is, no longer occsweep's: a user's entry exchanged there that could not be
  /// put back. Neither this object nor an interrupt removes it.
  void keep();

 private:
  std::filesystem::path path_;
  int fd_ = -1;
  bool kept_ = false;
};

/// Removes every registered temporary then exits 128 + signal on SIGINT, SIGTERM or SIGHUP; makes SIGXFSZ a
/// write error (EFBIG) instead of a kill. Call once at the start of main(). A SIGKILL cannot be caught: the next
/// run writing the same target names what it left, with the command that removes it (reportLeftoverTemporaries).
void removeTemporariesOnInterrupt();
/// Removes every registered temporary as an interrupt's cleaner does, prints `message` and exits with `status`: for a
/// failure no catch reaches (a bad_alloc in a destructor, command_line.cpp). A lock held past a second (by a thread
/// that failed inside a commit) leaves the temporaries to the next run, as a SIGKILL does.
[[noreturn]] void exitRemovingTemporaries(int status, const std::string& message);
/// What the interrupt's cleaner prints on stderr once the temporaries are removed, before the exit: for a command
/// that resumes, what it kept and the command that resumes (set by the command line). Empty: nothing.
void setInterruptMessage(std::string message);
/// The signal removeTemporariesOnInterrupt's handler has received (0: none). Its cleaning thread exits the process
/// soon after, however busy the machine: code that starts child processes checks this once its own handlers are
/// in place, so that no child is started that the exit would leave behind (cluster run-local).
[[nodiscard]] int interruptSignalReceived();

/// fork(2) for runChild: the child is registered, in one step under the registry's lock, as one the interrupt
/// handler kills (SIGKILL) and waits for before it removes temporaries. -1 once an interrupt arrived.
[[nodiscard]] pid_t forkRegisteredChild();
/// Forgets a registered child: called after it ended and before it is reaped (its PID is not reused meanwhile).
void unregisterChildProcess(pid_t pid);

/// Runs `step` holding the lock an interrupt's cleaning takes and keeps until the exit: when SIGINT, SIGTERM or SIGHUP
/// comes, `step` has run whole or not at all (a sweep's partial log renamed into place, one line appended to it).
/// `step` must not make, commit or remove a registered temporary, which takes the same lock.
void runWithoutInterruptCleaning(const std::function<void()>& step);

}  // namespace occsweep
