// Where an output may be written and what it may replace: an existing output only when it is occsweep's own output
// of the same kind and --force was given; never through a link, never one another name shares (docs/io.md, "Outputs
// and --force").
#pragma once

#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

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
/// rewrites it in a folder it resumes in, may replace (docs/io.md, "Ownership").
[[nodiscard]] ReplaceableOutput jsonOutput(const std::string& name, const std::string& format);

/// A text output of occsweep's in a format with no field of its own for a mark (a CSV, Markdown or LaTeX table): a
/// regular file with one name, its first line starting with `first_line`, holding the bytes occsweep marked
/// (markWrittenBytes, ownership.hpp): what --force may replace (docs/io.md, "Ownership"). Mark it before its
/// commit (OutputFile::markWritten).
[[nodiscard]] ReplaceableOutput textOutput(const std::string& name, const std::string& first_line);

/// The folders on the way to `dir` (itself included) that do not exist, innermost first: what a command about to
/// create `dir` makes, and removes again on failure with removeEmptyFolders.
[[nodiscard]] std::vector<std::filesystem::path> missingFolders(const std::filesystem::path& dir);

/// Removes each of `folders`, in order, only while it is empty: a folder holding anything (an entry someone put there
/// meanwhile) stays, and so does every folder on its way (docs/io.md, "Ownership").
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

}  // namespace occsweep
