// A file held by an exclusive lock while this process writes it (locked_file.hpp).
#include "occsweep/io/locked_file.hpp"
#include "occsweep/io/temporaries.hpp"

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <stdexcept>
#include <string>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

namespace occsweep {
namespace fs = std::filesystem;

namespace {

[[noreturn]] void anotherWriter(const fs::path& file) {
  throw std::runtime_error("another occsweep is writing " + file.string() +
                           " (a run writing the same output: wait for it to finish, or choose another output)");
}

[[noreturn]] void replacedMeanwhile(const fs::path& file) {
  throw std::runtime_error(file.string() + ": was replaced while occsweep was preparing it; what stands at its name "
                           "now is left as it is (docs/io.md, \"Ownership\")");
}

// Opens and locks `file` without following a symbolic link; -1 when it is not there.
int lockedDescriptor(const fs::path& file) {
  const int fd = ::open(file.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    if (errno == ENOENT) return -1;
    throw std::runtime_error(file.string() + ": cannot open (" + std::strerror(errno) + ")");
  }
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    ::close(fd);
    anotherWriter(file);
  }
  return fd;
}

}  // namespace

LockedFile::~LockedFile() {
  if (fd_ >= 0) ::close(fd_);
}

LockedFile& LockedFile::operator=(LockedFile&& o) noexcept {
  if (this != &o) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = std::exchange(o.fd_, -1);
  }
  return *this;
}

LockedFile LockedFile::existing(const fs::path& file) {
  LockedFile lock(lockedDescriptor(file));
  struct stat held {}, now {};
  // The writer that held it may have renamed it into place meanwhile: the lock is then on another file.
  if (!lock.held() || ::fstat(lock.fd_, &held) != 0 || ::lstat(file.c_str(), &now) != 0 || held.st_ino != now.st_ino ||
      held.st_dev != now.st_dev)
    anotherWriter(file);
  // A second name (a hard link a user made) would be written through as a symbolic link would (docs/io.md).
  if (held.st_nlink != 1)
    throw std::runtime_error(file.string() + ": has " + std::to_string(held.st_nlink) + " names (a hard link); "
                             "occsweep never writes into, replaces or removes a file it resumes that has another name "
                             "(even with --force): remove the other name, or choose another output");
  return lock;
}

namespace {

// The user's file, exchanged to the temporary's name, back at `file`: by a second exchange, else by a rename over this
// run's own new file (which `made` proves is what stands at `file`). Where both fail it stays at the temporary's
// name, kept and named: never removed as occsweep's.
[[noreturn]] void putBackUsersFile(RegisteredTemporary& claimed, const fs::path& file, const LockedFile& made) {
  const fs::path& temporary = claimed.path();
  if (::renameat2(AT_FDCWD, temporary.c_str(), AT_FDCWD, file.c_str(), RENAME_EXCHANGE) == 0)
    replacedMeanwhile(file);
  std::string why = std::string("exchange: ") + std::strerror(errno);
  const bool own_at_name = made.holdsFile(file);
  if (own_at_name && ::rename(temporary.c_str(), file.c_str()) == 0) replacedMeanwhile(file);
  why += own_at_name ? std::string("; rename: ") + std::strerror(errno) : "; another file stands at its name now";
  claimed.keep();
  throw std::runtime_error(file.string() + ": was replaced while occsweep was preparing it, and could not be put "
                           "back (" + why + "): the file that stood there is now at " + temporary.string() +
                           ", which occsweep never removes" +
                           (own_at_name ? "; occsweep's new file is at " + file.string() : ""));
}

// Puts the new file (`claimed`, locked by `made`) at `file` in place of the one `replacing` holds,
// and removes that one. Exchanged atomically, then checked: a file a user put at the name meanwhile (a sweep
// prepares its data for minutes) goes back, and the run stops naming it.
void replaceHeldFile(RegisteredTemporary& claimed, const fs::path& file, const LockedFile& replacing,
                        const LockedFile& made) {
  const fs::path& temporary = claimed.path();
  bool users_file_exchanged = false;
  runWithoutInterruptCleaning([&] {
    if (::renameat2(AT_FDCWD, temporary.c_str(), AT_FDCWD, file.c_str(), RENAME_EXCHANGE) != 0) {
      if (errno != EINVAL && errno != ENOSYS)
        throw std::runtime_error(file.string() + ": cannot replace (" + std::strerror(errno) + ")");
      if (!replacing.holdsFile(file)) replacedMeanwhile(file);  // no exchange on this file system
      fs::rename(temporary, file);
    } else if (!replacing.holdsFile(temporary)) {
      users_file_exchanged = true;
      return;
    }
    replacing.removeHeldFile(temporary);  // the old file, now at the temporary's name (if exchanged)
  });
  if (users_file_exchanged) putBackUsersFile(claimed, file, made);
}

}  // namespace

LockedFile LockedFile::publish(const fs::path& file, const LockedFile* replacing,
                                 const std::function<void(const fs::path&)>& make) {
  // Made and registered as OutputFile's temporaries are (docs/io.md, "Ownership"): an interrupt removes
  // it while it is the file made there; what a kill leaves the next run names. A user's file is at that name only
  // while an exchange is undone (putBackUsersFile), or once kept.
  // Its destructor removes the temporary's name, and only while it names the file made there.
  RegisteredTemporary claimed(file, TemporaryKind::File);  // `make` fills it, never creates it
  const fs::path& temporary = claimed.path();
  make(temporary);
  LockedFile lock(lockedDescriptor(temporary));
  // Locked before it appears under its name: a second process finds it locked. Neither the exchange nor the rename
  // below replaces a file.
  if (replacing) {
    replaceHeldFile(claimed, file, *replacing, lock);
    return lock;
  }
  // Renamed without replacing (never a second name a kill could leave behind), else linked: neither replaces a file.
  runWithoutInterruptCleaning([&] {
    if (::renameat2(AT_FDCWD, temporary.c_str(), AT_FDCWD, file.c_str(), RENAME_NOREPLACE) != 0) {
      if (errno == EEXIST) anotherWriter(file);
      if ((errno != EINVAL && errno != ENOSYS) || ::link(temporary.c_str(), file.c_str()) != 0) {
        if (errno == EEXIST) anotherWriter(file);
        throw std::runtime_error(file.string() + ": cannot create (" + std::strerror(errno) + ")");
      }
    }
  });
  return lock;
}

bool LockedFile::holdsFile(const fs::path& file) const noexcept {
  struct stat held {}, now {};
  if (fd_ < 0 || ::fstat(fd_, &held) != 0 || ::lstat(file.c_str(), &now) != 0) return false;
  return held.st_dev == now.st_dev && held.st_ino == now.st_ino;
}

bool LockedFile::removeHeldFile(const fs::path& file) const noexcept {
  return holdsFile(file) && ::unlink(file.c_str()) == 0;
}

fs::path LockedFile::heldFilePath() const {
  if (fd_ < 0) throw std::logic_error("LockedFile::heldFilePath: no file held");
  return fs::path("/proc/self/fd") / std::to_string(fd_);
}

}  // namespace occsweep
