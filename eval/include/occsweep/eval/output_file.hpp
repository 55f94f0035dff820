// Every file and folder occsweep writes goes through here: built under a temporary name in the target's folder,
// checked, and renamed into place only when complete; an existing output is replaced only when it is occsweep's
// own output of the same kind and --force was given (docs/robustness.md, "Outputs, temporaries and --force").
#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <ostream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <sys/types.h>
#include <utility>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "occsweep/eval/ownership.hpp"

namespace occsweep {

/// A refused or failed output. The message names the file and says why ("no space left on device", ...).
class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// An output that appeared or changed at the target while occsweep wrote it: kept, and nothing was replaced. Not a
/// failed write: what the command made (a sweep's partial log) stays for a run after the user moved it away.
class OutputConflict : public OutputError {
 public:
  using OutputError::OutputError;
};

/// `file: reason` for an errno value: ENOSPC is "no space left on device", EFBIG the file-size limit.
[[nodiscard]] std::string writeFailure(const std::filesystem::path& file, int error_number);

/// What a command writes, and how occsweep recognises its own previous output of that kind.
struct ReplaceableOutput {
  std::string name;  ///< "data set folder", "results file", ...
  std::function<bool(const std::filesystem::path&)> is_own;
};

/// A JSON output of occsweep's, proven by its own "format" field being `format`: what --force, or a command that
/// rewrites it in a folder it resumes in, may replace (docs/robustness.md, "Ownership").
[[nodiscard]] ReplaceableOutput jsonOutput(const std::string& name, const std::string& format);

/// A text output of occsweep's in a format with no field of its own for a mark (a CSV, Markdown or LaTeX table): a
/// regular file with one name, its first line starting with `first_line`, holding the bytes occsweep marked
/// (markWrittenBytes, ownership.hpp): what --force may replace (docs/robustness.md, "Ownership"). Mark it before its
/// commit (OutputFile::markWritten).
[[nodiscard]] ReplaceableOutput textOutput(const std::string& name, const std::string& first_line);

/// The folders on the way to `dir` (itself included) that do not exist, innermost first: what a command about to
/// create `dir` makes, and removes again on failure with removeEmptyFolders.
[[nodiscard]] std::vector<std::filesystem::path> missingFolders(const std::filesystem::path& dir);

/// Removes each of `folders`, in order, only while it is empty: a folder holding anything (an entry someone put there
/// meanwhile) stays, and so does every folder on its way (docs/robustness.md, "Ownership").
void removeEmptyFolders(const std::vector<std::filesystem::path>& folders) noexcept;

/// The target as a clean path: a trailing slash dropped, `.` and `..` resolved against the current folder.
[[nodiscard]] std::filesystem::path outputTarget(const std::filesystem::path& target);

/// Refuses an existing `target` (exit 2 through OutputError) unless `force` and `kind.is_own(target)`. An empty
/// folder is not an output and is replaced. The current folder or one of its parents is always refused. The target's
/// state is remembered: a later commit to it replaces that state only (nothing created or changed meanwhile).
void checkOutputTarget(const std::filesystem::path& target, bool force, const ReplaceableOutput& kind);

/// Refuses (OutputError) a `target` whose companion file `target + suffix` (a sweep's partial log, a map's
/// .ot.json) would pass the 255 bytes a file name may have, naming the longest name that fits.
void requireCompanionName(const std::filesystem::path& target, const std::string& suffix);

/// Two outputs that cannot both be written: one file, or one under the other, read as the writer reads them
/// (absolute, `..` taken lexically, a trailing '/' dropped) or as the system resolves symbolic links.
[[nodiscard]] bool outputsCollide(const std::filesystem::path& a, const std::filesystem::path& b);

/// Refuses (OutputError naming the flags) outputs of one command that collide, and an output under an existing
/// file or a broken symbolic link, before any is written; empty paths are outputs not asked for.
void requireSeparateOutputs(const std::vector<std::pair<std::string, std::filesystem::path>>& flagged_outputs);

struct TargetState;

/// One file written under `.NAME.tmp-PID-TOKEN` beside `target`; `commit()` flushes, checks and renames it into
/// place, only over what checkOutputTarget accepted, as it was then; with no such check, only where nothing stands:
/// an output that appeared or changed meanwhile is kept and the commit fails. Destroyed uncommitted (an exception),
/// it removes the temporary.
/// Every write is checked: the first failure throws OutputError at the latest in `commit()`.
class OutputFile {
 public:
  explicit OutputFile(const std::filesystem::path& target);
  ~OutputFile();
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  [[nodiscard]] std::ostream& stream();
  [[nodiscard]] const std::filesystem::path& temporary() const { return temporary_; }
  /// Flushes, checks, syncs and closes the temporary: another program may then read or write it by its path.
  void finish();
  /// finish(), then marks the bytes written (markWrittenBytes): a text output a later --force may replace.
  void markWritten();
  void commit();
  /// The outputs of one command, committed together: every target is checked first, so that one created or
  /// changed meanwhile (OutputConflict) or a failed write stops the command before any of them is committed.
  static void commitTogether(const std::vector<OutputFile*>& files);

 private:
  struct Buffer;
  std::filesystem::path target_, temporary_;
  std::unique_ptr<TargetState> checked_;
  std::unique_ptr<Buffer> buffer_;
  std::unique_ptr<std::ostream> stream_;
  bool committed_ = false;
};

/// One folder built under `.NAME.tmp-PID-TOKEN` beside `target`; `commit()` renames it into place, replacing an
/// existing target only as OutputFile does. Destroyed uncommitted, it removes the temporary folder.
class OutputFolder {
 public:
  explicit OutputFolder(const std::filesystem::path& target);
  ~OutputFolder();
  OutputFolder(const OutputFolder&) = delete;
  OutputFolder& operator=(const OutputFolder&) = delete;

  [[nodiscard]] const std::filesystem::path& path() const { return temporary_; }
  void commit();

 private:
  std::filesystem::path target_, temporary_;
  std::unique_ptr<TargetState> checked_;
  bool committed_ = false;
};

/// Renames a finished file `from` (a sweep's partial store) to `target` under OutputFile::commit's rule: only over
/// what checkOutputTarget accepted; an output created or changed meanwhile is kept (OutputError).
void renameIntoPlace(const std::filesystem::path& from, const std::filesystem::path& target);

/// What a ClaimedTemporary makes at its name: an empty file or an empty folder.
enum class TemporaryKind { File, Folder };

/// A temporary of `target` (ownership.hpp), made exclusively, empty, and registered in one step: removed with what
/// it holds (and an SQLite `-journal` beside it) on SIGINT, SIGTERM or SIGHUP, or when destroyed, while it is the
/// entry made there. For writers that fill it themselves and then link or rename it into place (a sweep's partial
/// output, a script's figures). They open it without creating it: a temporary an interrupt has removed is then never
/// made again before the exit.
class ClaimedTemporary {
 public:
  ClaimedTemporary(const std::filesystem::path& target, TemporaryKind kind);
  ~ClaimedTemporary();
  ClaimedTemporary(const ClaimedTemporary&) = delete;
  ClaimedTemporary& operator=(const ClaimedTemporary&) = delete;
  [[nodiscard]] const std::filesystem::path& path() const { return path_; }
  /// Leaves what stands at path() where it is, no longer occsweep's: a user's entry exchanged there that could not be
  /// put back. Neither this object nor an interrupt removes it.
  void keep();
  [[nodiscard]] bool kept() const { return kept_; }

 private:
  std::filesystem::path path_;
  bool kept_ = false;
};

/// `bytes` as `target`, atomically (OutputFile).
void writeFileAtomically(const std::filesystem::path& target, std::string_view bytes);
/// `j` as `file`, one space of indent and a final newline, atomically: every JSON output of occsweep.
void writeJsonAtomically(const nlohmann::json& j, const std::filesystem::path& file);

/// `bytes` as `file` directly, every write checked: for files inside an OutputFolder's temporary folder.
void writeFileChecked(const std::filesystem::path& file, std::string_view bytes);
/// A folder made at `folder` (mkdir, checked: OutputError naming it).
void makeFolderChecked(const std::filesystem::path& folder);
/// A symbolic link at `link` to `points_to` (checked: OutputError naming it).
void makeSymlinkChecked(const std::filesystem::path& points_to, const std::filesystem::path& link);

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

}  // namespace occsweep
