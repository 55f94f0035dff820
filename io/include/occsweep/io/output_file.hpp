// Every file and folder occsweep writes: built under a temporary name in the target's folder, checked, and renamed
// into place only when complete, over only what checkOutputTarget accepted (docs/io.md, "Outputs and --force").
#pragma once

#include <filesystem>
#include <memory>
#include <ostream>
#include <string_view>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "occsweep/io/output_target.hpp"
#include "occsweep/io/temporaries.hpp"

namespace occsweep {

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
  [[nodiscard]] const std::filesystem::path& temporary() const { return temporary_.path(); }
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
  std::filesystem::path target_;
  RegisteredTemporary temporary_;
  std::unique_ptr<TargetState> checked_;
  std::unique_ptr<Buffer> buffer_;
  std::unique_ptr<std::ostream> stream_;
};

/// One folder built under `.NAME.tmp-PID-TOKEN` beside `target`; `commit()` renames it into place, replacing an
/// existing target only as OutputFile does. Destroyed uncommitted, it removes the temporary folder.
class OutputFolder {
 public:
  explicit OutputFolder(const std::filesystem::path& target);
  ~OutputFolder();
  OutputFolder(const OutputFolder&) = delete;
  OutputFolder& operator=(const OutputFolder&) = delete;

  [[nodiscard]] const std::filesystem::path& path() const { return temporary_.path(); }
  void commit();

 private:
  std::filesystem::path target_;
  RegisteredTemporary temporary_;
  std::unique_ptr<TargetState> checked_;
};

/// Renames a finished file `from` (a sweep's partial store) to `target` under OutputFile::commit's rule: only over
/// what checkOutputTarget accepted; an output created or changed meanwhile is kept (OutputError).
void renameIntoPlace(const std::filesystem::path& from, const std::filesystem::path& target);

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

}  // namespace occsweep
