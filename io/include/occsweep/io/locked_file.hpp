// A file held by an exclusive lock (flock) while this process writes it, and written through its descriptor, never by
// its name: a resumable output (a sweep's partial output). A second process on the same file stops with "another
// occsweep is writing FILE"; a user who moves the file away keeps what they put at its name (docs/io.md,
// "Ownership").
#pragma once

#include <filesystem>
#include <functional>
#include <utility>

namespace occsweep {

class LockedFile {
 public:
  LockedFile() = default;
  ~LockedFile();
  LockedFile(LockedFile&& o) noexcept : fd_(std::exchange(o.fd_, -1)) {}
  LockedFile& operator=(LockedFile&& o) noexcept;
  /// Locks the existing regular `file`, never following a symbolic link. Throws when another process holds it, or
  /// when the file has another name (a hard link). Not held when there is no file.
  [[nodiscard]] static LockedFile existing(const std::filesystem::path& file);
  /// A new file: `make` writes it at a registered temporary beside `file` (never creating it), which is locked, then
  /// put at `file`: in place of the one `replacing` holds (a file put at the name meanwhile stays, and this throws),
  /// or, without `replacing`, only if there is none (another process made one meanwhile: thrown as above). Nothing
  /// is left at the temporary on an error.
  [[nodiscard]] static LockedFile publish(const std::filesystem::path& file, const LockedFile* replacing,
                                          const std::function<void(const std::filesystem::path&)>& make);
  [[nodiscard]] bool held() const { return fd_ >= 0; }
  /// The open file this lock holds (-1: none).
  [[nodiscard]] int descriptor() const { return fd_; }
  /// Removes `file` only when it is still the file this lock holds (device and inode): a file someone put at that
  /// name meanwhile stays. True when it removed it.
  bool removeHeldFile(const std::filesystem::path& file) const noexcept;
  /// True when `file` is still the file this lock holds (device and inode).
  [[nodiscard]] bool holdsFile(const std::filesystem::path& file) const noexcept;
  /// A path that opens the file this lock holds, whatever now stands at its name (/proc/self/fd).
  [[nodiscard]] std::filesystem::path heldFilePath() const;

 private:
  explicit LockedFile(int fd) : fd_(fd) {}
  int fd_ = -1;
};

}  // namespace occsweep
