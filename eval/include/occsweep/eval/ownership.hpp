// Proof that an entry beside an output is occsweep's to remove (docs/robustness.md, "Ownership"). A name alone
// proves nothing (a user may keep `r.json.old-2023`), nor do bytes a user could write. A temporary is occsweep's
// when its name carries a random token that the run which made it recorded in occsweep's ledger, beside the
// temporary's entry (its folder's inode and birth time, and its name) before creating it, and the entry's own inode
// and birth time once made.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>

namespace occsweep {

/// The longest file name (one path component) Linux file systems take: NAME_MAX.
inline constexpr std::size_t kFileNameMax = 255;

/// The ledger folder: $OCCSWEEP_STATE_DIR, else $XDG_STATE_HOME/occsweep, else $HOME/.local/state/occsweep; empty
/// when none is set. One file per live temporary, named by its token.
[[nodiscard]] std::filesystem::path ownershipLedger();

/// A temporary this process may create: `.NAME.tmp-PID-TOKEN` beside `target`, TOKEN 128 random bits in hex, NAME
/// cut where the whole would pass the 255 bytes a file name may have.
struct TemporaryClaim {
  std::filesystem::path path;
  std::string token;
  bool recorded = false;  ///< false when the ledger cannot be written: a kill then leaves the temporary for the user
};

/// Chooses a temporary's name for `target` (a clean absolute or relative path) and records it in the ledger.
[[nodiscard]] TemporaryClaim claimTemporary(const std::filesystem::path& target);

/// Adds to a temporary's record, once it is made, the entry's own inode and birth time: an entry a user puts at that
/// name later (a backup restored after a kill) is another entry, and stays. A kill between the making and this
/// leaves a record without them, which proves the folder and the name only.
void recordTemporaryMade(const TemporaryClaim& claim);

/// Adds to a temporary folder's record, before it is made, an entry the folder will hold (`relative` to it): a
/// killed run's folder is removed only when every entry in it is one its record lists, and each listed entry is
/// the one made there (recordTemporaryContentMade); a kill between the two lines leaves an entry proven by its name.
void recordTemporaryContent(const TemporaryClaim& claim, const std::filesystem::path& relative);

/// Adds to a temporary folder's record the inode and birth time of the entry at `relative` once it is whole, and a
/// file's size and modification time: one a user wrote into since is theirs.
void recordTemporaryContentMade(const TemporaryClaim& claim, const std::filesystem::path& relative);

/// Drops the ledger record of a temporary that was committed or removed.
void releaseTemporary(const TemporaryClaim& claim);

/// The name a user knows for a temporary's component (`.NAME.tmp-PID-TOKEN` is `NAME`); other names unchanged.
[[nodiscard]] std::string outputNameOf(const std::string& component);

/// True when `entry`, beside output `target`, is a temporary of `target` that occsweep recorded as that entry and
/// whose process is gone: on this host, another boot, or this boot and PID namespace and no process of its PID
/// and start time. A record of another host or PID namespace (a shared home folder) never proves it gone.
[[nodiscard]] bool isStaleTemporaryOf(const std::filesystem::path& entry, const std::filesystem::path& target);

/// Removes a temporary of this run at `path` (a file, or a folder with what it holds) and SQLite's rollback journal
/// named after it (`path-journal`, what a kill of a store being written there leaves); false when `path` could not be
/// removed.
bool removeTemporaryEntry(const std::filesystem::path& path) noexcept;

/// Removes `entry` and its record when isStaleTemporaryOf; true if it did. A folder goes with what its record proves
/// it held (recordTemporaryContent); an entry it does not prove (a user's file moved in after the kill) stays, with
/// the folders on its way, and a warning names the folder, which is the user's from then on.
bool removeStaleTemporary(const std::filesystem::path& entry, const std::filesystem::path& target);

/// Records an output occsweep has just committed whose format has no field of its own to carry a mark (CSV, Markdown
/// and LaTeX tables): its entry (its folder's device and inode, and its name), size and FNV-1a hash of its bytes, in
/// the ledger's `outputs/` folder.
/// Nothing is recorded where the ledger cannot be written; such a file is then never replaced (--force refuses it).
void recordTextOutput(const std::filesystem::path& file);

/// True when `file` holds exactly the bytes occsweep recorded for this entry (recordTextOutput), whatever way its path
/// is spelt: a file a user wrote, a copy of occsweep's, or occsweep's edited by hand, is not occsweep's to replace.
[[nodiscard]] bool isRecordedTextOutput(const std::filesystem::path& file);

/// Records, before it is made, an entry occsweep makes at a fixed name and fills later (a run-local task's running
/// marker, which gets the task's pid once the task starts, and its log): its entry (entryIdentity), in the ledger's
/// `made/` folder. recordMadeEntry adds its own inode and birth time once made; a kill between the two leaves a
/// record that proves the folder and the name only (as for temporaries). Its bytes are not part of the proof:
/// occsweep changes them. Records of entries gone or replaced are dropped when a process first writes one; nothing
/// is recorded where the ledger cannot be written.
void claimMadeEntry(const std::filesystem::path& entry);
void recordMadeEntry(const std::filesystem::path& entry);
/// Adds to a made entry's record, after occsweep's last write to it, its size, modification and status-change times.
/// On a file system that keeps no birth time, a file a user makes at that name later may get the same inode: such an
/// entry is proven only by this stamp, so one occsweep was still writing when a kill came stays for the user.
void recordMadeEntryWritten(const std::filesystem::path& entry);

/// True when `entry` is the very entry recorded at that place (a file put there since is another). With a
/// `descriptor`, the file it has open is compared with the record instead of what stands at the name now: a reader
/// that checks a file it has already opened (and locked) is never fooled by a swap of names in between.
[[nodiscard]] bool isRecordedMadeEntry(const std::filesystem::path& entry, int descriptor = -1);

/// True when the file system keeps `entry`'s birth time, so that its inode and birth time alone prove it
/// (recordMadeEntry). Elsewhere a made entry occsweep appends to needs recordMadeEntryWritten after every write.
[[nodiscard]] bool keepsBirthTime(const std::filesystem::path& entry);

/// Drops the record of an entry occsweep removed.
void forgetMadeEntry(const std::filesystem::path& entry);

}  // namespace occsweep
