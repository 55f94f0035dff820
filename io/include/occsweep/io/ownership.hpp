// What occsweep may remove, by the rule git (`index.lock`), SQLite (`-journal`) and rsync (`--partial-dir`) follow
// (docs/io.md, "Ownership"): the outputs its command line names and the names it reserves beside them, and
// a temporary only in the process that made it. No state outside the outputs' folders: a killed run's temporary is
// reported by the next run with the command that removes it, never removed by occsweep.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>

namespace occsweep {

/// The longest file name (one path component) Linux file systems take: NAME_MAX.
inline constexpr std::size_t kFileNameMax = 255;

/// A name for a new temporary of `target` (a clean absolute or relative path): `.NAME.tmp-PID-TOKEN` beside it,
/// TOKEN 128 random bits in hex, NAME cut where the whole would pass the 255 bytes a file name may have. The caller
/// creates it exclusively (O_EXCL, mkdir).
[[nodiscard]] std::filesystem::path temporaryNameFor(const std::filesystem::path& target);

/// The name a user knows for a temporary's component (`.NAME.tmp-PID-TOKEN` is `NAME`); other names unchanged.
[[nodiscard]] std::string outputNameOf(const std::string& component);

/// `file` as the user knows it: each temporary component `.NAME.tmp-PID-TOKEN` shown as `NAME`, the output being
/// written. Every message about a write names this.
[[nodiscard]] std::filesystem::path outputPathOf(const std::filesystem::path& file);

/// True when `entry` is named as a temporary of `target` whose process does not run on this machine: what a killed
/// run left, or what a run on another machine sharing the folder is writing (its process cannot be seen from here).
[[nodiscard]] bool isLeftoverTemporaryOf(const std::filesystem::path& entry, const std::filesystem::path& target);

/// Prints on stderr, once per target and process, each leftover temporary of `target` (and SQLite's journal beside
/// it) with the command that removes it. occsweep never removes them: it cannot tell a killed run's from an entry a
/// user made at that name, or from one another machine's run is writing.
void reportLeftoverTemporaries(const std::filesystem::path& target);

/// Why the entry at a name occsweep reserves is not a regular file with one name ("" when it is; else "is a symbolic
/// link", "is not a regular file", "has 2 names ..."), and its first `max_bytes` bytes in `head`: read through a
/// descriptor opened without following a link or waiting on a FIFO, and only while it is the entry looked at.
[[nodiscard]] std::string readReservedFile(const std::filesystem::path& file, std::size_t max_bytes,
                                           std::string& head);

/// Why the entry at a name occsweep reserves (a run-local lock, marker or task log, a table) is not occsweep's to
/// write into, replace or remove: "" when readReservedFile accepts it and it starts with `mark` (or, with
/// `empty_is_own`, is empty: what a kill right after its creation leaves); else why not.
[[nodiscard]] std::string notOwnReservedFile(const std::filesystem::path& file, const std::string& mark,
                                             bool empty_is_own = false);

/// notOwnReservedFile of the file open at `fd` (not what its name holds by now): for a file occsweep opens before it
/// knows whose it is (run-local's lock, opened to be locked).
[[nodiscard]] std::string notOwnOpenFile(int fd, const std::string& mark, bool empty_is_own = false);

/// Marks a file occsweep has written whole in a format with no field of its own for a mark (a CSV, Markdown or LaTeX
/// table, a PDF or SVG figure): the FNV-1a hash of its bytes in its extended attribute `user.occsweep.fnv1a`, which
/// stays with the file. Nothing where the file system keeps no user attributes: such a file is then never replaced.
void markWrittenBytes(const std::filesystem::path& file);

/// True when `file` holds exactly the bytes occsweep marked (markWrittenBytes): a file a user wrote, or occsweep's
/// edited since, is not occsweep's to replace.
[[nodiscard]] bool holdsMarkedBytes(const std::filesystem::path& file);

/// Removes a temporary this process made at `path` (a file, or a folder with what it holds) and SQLite's rollback
/// journal named after it (`path-journal`); false when `path` could not be removed. A symbolic link is never removed.
bool removeTemporaryEntry(const std::filesystem::path& path) noexcept;

}  // namespace occsweep
