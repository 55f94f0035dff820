// What the writers inside io share: the lock an interrupt's cleaner takes and keeps until the exit, this process's
// live temporaries, and each output target as checkOutputTarget accepted it (docs/io.md).
#pragma once

#include <ctime>
#include <filesystem>
#include <functional>
#include <map>
#include <mutex>
#include <sys/types.h>

#include "occsweep/io/output_target.hpp"
#include "occsweep/io/temporaries.hpp"

namespace occsweep {

/// What stood at an output's path: nothing, an empty folder (replaced, it holds nothing), or an entry named by its
/// device, inode, size and modification time.
struct TargetState {
  bool exists = false, empty_folder = false;
  dev_t device = 0;
  ino_t inode = 0;
  off_t size = 0;
  timespec modified{};
  /// The kind's own check, kept when --force accepted the entry: run again on a folder swapped out at commit, whose
  /// deeper entries its top's time does not show.
  std::function<bool(const std::filesystem::path&)> is_own;
};

}  // namespace occsweep

namespace occsweep::io_detail {

/// The registry's lock. Never destroyed: the cleaning thread may still use it while static objects are destroyed.
std::mutex& registryMutex();

/// Registers `path` and makes its entry (an empty file, opened for writing, or an empty folder) exclusively, in one
/// step under the registry's lock: an interrupt's cleaner either sees and removes it, or it is never made. The file's
/// descriptor (0 for a folder); on failure -1 with errno set and nothing registered.
int registerAndCreate(const std::filesystem::path& path, TemporaryKind kind);
/// Drops a temporary (removed, committed or kept) from the registry.
void unregisterTemporary(const std::filesystem::path& path);
/// unregisterTemporary for a caller that holds the registry's lock.
void unregisterTemporaryLocked(const std::filesystem::path& path);
/// Whether `path` is a registered temporary and another entry (or none) stands at its name. The caller holds the
/// registry's lock.
bool temporaryReplaced(const std::filesystem::path& path);
/// Whether the entry this run made as its temporary `path` still stands there (not a user's entry put at its name,
/// nor one committed, kept or removed). Takes the registry's lock.
bool isMadeEntry(const std::filesystem::path& path);

TargetState stateOf(const std::filesystem::path& path);
bool sameEntry(const TargetState& a, const TargetState& b);
/// Targets checkOutputTarget accepted, as they were then, by absolute path (under registryMutex).
std::map<std::filesystem::path, TargetState>& checkedTargets();
std::filesystem::path targetKey(const std::filesystem::path& target);
/// The state checkOutputTarget accepted at `target`; none (so: nothing may be replaced) when it was not checked.
TargetState checkedState(const std::filesystem::path& target);

/// An OutputError for a failed write (writeFailure's message).
[[noreturn]] inline void failWrite(const std::filesystem::path& file, int error_number) {
  throw OutputError(writeFailure(file, error_number));
}
[[noreturn]] inline void failWrite(const std::filesystem::filesystem_error& e) {
  failWrite(e.path1().empty() ? std::filesystem::path("?") : e.path1(), e.code().value());
}

}  // namespace occsweep::io_detail
