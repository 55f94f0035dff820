// Atomic outputs: built under a temporary name, committed by a rename over only what checkOutputTarget accepted
// (docs/io.md, "Outputs and --force").
#include "occsweep/io/output_file.hpp"
#include "occsweep/io/ownership.hpp"
#include "output_registry.hpp"

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <streambuf>
#include <sys/stat.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

namespace occsweep {
namespace fs = std::filesystem;
using namespace io_detail;

namespace {

// The target as a clean path (outputTarget), its folder made.
fs::path preparedTarget(const fs::path& target) {
  const fs::path t = outputTarget(target);
  if (!t.has_parent_path()) return t;
  try {
    fs::create_directories(t.parent_path());
  } catch (const fs::filesystem_error& e) {
    failWrite(e);
  }
  return t;
}

[[noreturn]] void appeared(const fs::path& target, const char* what) {
  throw OutputConflict(outputPathOf(target).string() + ": " + what + " while occsweep was writing it: nothing was " +
                       "replaced (write to another path, or move it away and run again)");
}

// rename(2) that never replaces: an output created meanwhile stays (link-then-unlink where the file system has no
// RENAME_NOREPLACE; a folder there is renamed after the check, the one moment left open).
void renameNoReplace(const fs::path& from, const fs::path& to, bool folder) {
  if (::renameat2(AT_FDCWD, from.c_str(), AT_FDCWD, to.c_str(), RENAME_NOREPLACE) == 0) return;
  if (errno == EEXIST) appeared(to, "was created");
  if (errno != EINVAL && errno != ENOSYS) failWrite(to, errno);
  if (folder) {
    if (::rename(from.c_str(), to.c_str()) != 0) failWrite(to, errno);
  } else {
    if (::link(from.c_str(), to.c_str()) != 0) errno == EEXIST ? appeared(to, "was created") : failWrite(to, errno);
    ::unlink(from.c_str());
  }
}

// Puts `temporary` at `target` when the target is still as checked: absent stays absent, an empty folder is
// replaced, an existing output (accepted by checkOutputTarget, or present when writing began) is still the same
// entry. Called under registryMutex.
// Throws OutputConflict when `target` is no longer as checked (created, or another entry than the one accepted).
void requireAsChecked(const fs::path& target, const TargetState& checked, const TargetState& now) {
  if (!now.exists || now.empty_folder) return;
  if (!checked.exists || checked.empty_folder) appeared(target, "was created");
  if (!sameEntry(checked, now)) appeared(target, "was changed");
}

// The user's folder, exchanged out of `target` after it changed meanwhile, goes back. Where the file system refuses
// the second exchange it stays at the temporary's name, no longer occsweep's to remove: dropped from the registry
// (so that no interrupt removes it) and named. Called under registryMutex.
[[noreturn]] void exchangeBack(const fs::path& temporary, const fs::path& target) {
  if (::renameat2(AT_FDCWD, temporary.c_str(), AT_FDCWD, target.c_str(), RENAME_EXCHANGE) == 0)
    appeared(target, "was changed");
  const int e = errno;
  unregisterTemporaryLocked(temporary);
  const std::string shown = outputPathOf(target).string();
  throw OutputConflict(shown + ": was changed while occsweep was writing it, and could not be put back (" +
                       std::strerror(e) + "): what stood there is now at " + temporary.string() +
                       ", occsweep's new output at " + shown + "; occsweep removes neither");
}

void placeOutput(const fs::path& temporary, const fs::path& target, const TargetState& checked, bool folder) {
  // What the writer filled, not an entry put at the temporary's name meanwhile (renamed, it would be the output).
  if (temporaryReplaced(temporary))
    throw OutputConflict(temporary.string() + ": occsweep's temporary for " + outputPathOf(target).string() +
                         " was replaced or removed while occsweep was writing it: nothing was committed, and what " +
                         "stands there is left as it is");
  const TargetState now = stateOf(target);
  std::error_code ec;
  requireAsChecked(target, checked, now);
  if (now.exists && !now.empty_folder) {
    if (!folder) {
      if (::rename(temporary.c_str(), target.c_str()) != 0) failWrite(target, errno);
      return;
    }
    // Swapped in one step: no moment without either the old or the new folder. The old one, now under the
    // registered temporary name, is removed only if every entry in it is still occsweep's; else swapped back.
    if (::renameat2(AT_FDCWD, temporary.c_str(), AT_FDCWD, target.c_str(), RENAME_EXCHANGE) == 0) {
      if (checked.is_own && !checked.is_own(temporary)) exchangeBack(temporary, target);
      fs::remove_all(temporary, ec);
      return;
    }
    if (errno != EINVAL && errno != ENOSYS) failWrite(target, errno);
    if (checked.is_own && !checked.is_own(target)) appeared(target, "was changed");
    fs::remove_all(target, ec);  // no RENAME_EXCHANGE on this file system
  } else if (now.empty_folder) {
    fs::remove(target, ec);  // an empty folder holds nothing of the user's
  }
  renameNoReplace(temporary, target, folder);
}

void recordCommitted(const fs::path& target) { checkedTargets()[targetKey(target)] = stateOf(target); }

}  // namespace

// ---- OutputFile ----

// A stream buffer on a file descriptor that keeps the errno of the first failed write (ENOSPC, EFBIG, ...),
// which std::ofstream loses.
struct OutputFile::Buffer : std::streambuf {
  int fd = -1;
  int error = 0;
  char data[1 << 16];

  explicit Buffer(int descriptor) : fd(descriptor) { setp(data, data + sizeof data); }

  bool drain() {
    for (char* p = pbase(); p < pptr();) {
      const ssize_t n = ::write(fd, p, std::size_t(pptr() - p));
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) {
        error = n < 0 ? errno : EIO;
        return false;
      }
      p += n;
    }
    setp(data, data + sizeof data);
    return true;
  }
  int_type overflow(int_type c) override {
    if (error != 0 || !drain()) return traits_type::eof();
    if (!traits_type::eq_int_type(c, traits_type::eof())) {
      *pptr() = traits_type::to_char_type(c);
      pbump(1);
    }
    return traits_type::not_eof(c);
  }
  int sync() override { return error == 0 && drain() ? 0 : -1; }
};

OutputFile::OutputFile(const fs::path& target)
    : target_(preparedTarget(target)),
      temporary_(target_, TemporaryKind::File),
      checked_(std::make_unique<TargetState>(checkedState(target_))),
      buffer_(std::make_unique<Buffer>(temporary_.takeDescriptor())),
      stream_(std::make_unique<std::ostream>(buffer_.get())) {}

OutputFile::~OutputFile() {
  if (buffer_->fd >= 0) ::close(buffer_->fd);
}

std::ostream& OutputFile::stream() { return *stream_; }

void OutputFile::finish() {
  if (buffer_->fd < 0) return;
  stream_->flush();
  if (buffer_->error != 0 || !*stream_) failWrite(target_, buffer_->error != 0 ? buffer_->error : EIO);
  // fsync: a rename is only as durable as the data it points at (a crash right after it must not leave zeros).
  if (::fsync(buffer_->fd) != 0 && errno != EINVAL) failWrite(target_, errno);
  const int fd = buffer_->fd;
  buffer_->fd = -1;
  if (::close(fd) != 0) failWrite(target_, errno);
}

void OutputFile::markWritten() {
  finish();
  markWrittenBytes(temporary_.path());
}

void OutputFile::commit() { commitTogether({this}); }

void OutputFile::commitTogether(const std::vector<OutputFile*>& files) {
  for (OutputFile* f : files) f->finish();  // every write checked before any rename
  std::unique_lock lock(registryMutex());    // no rename once an interrupt's cleaning has begun (cleanOnInterrupt)
  for (OutputFile* f : files) requireAsChecked(f->target_, *f->checked_, stateOf(f->target_));
  for (OutputFile* f : files) {
    placeOutput(f->temporary_.path(), f->target_, *f->checked_, false);
    recordCommitted(f->target_);
  }
}

// ---- OutputFolder ----

OutputFolder::OutputFolder(const fs::path& target)
    : target_(preparedTarget(target)),
      temporary_(target_, TemporaryKind::Folder),
      checked_(std::make_unique<TargetState>(checkedState(target_))) {}

OutputFolder::~OutputFolder() = default;

void OutputFolder::commit() {
  std::unique_lock lock(registryMutex());  // no rename once an interrupt's cleaning has begun (cleanOnInterrupt)
  placeOutput(temporary_.path(), target_, *checked_, true);
  recordCommitted(target_);
}

// ---- one-call writers ----

void renameIntoPlace(const fs::path& from, const fs::path& target) {
  const fs::path t = outputTarget(target);
  const TargetState checked = checkedState(t);
  std::unique_lock lock(registryMutex());
  placeOutput(from, t, checked, false);
  recordCommitted(t);
}

void writeFileAtomically(const fs::path& target, std::string_view bytes) {
  OutputFile out(target);
  out.stream().write(bytes.data(), std::streamsize(bytes.size()));
  out.commit();
}

void writeJsonAtomically(const nlohmann::json& j, const fs::path& file) { writeFileAtomically(file, j.dump(1) + '\n'); }

void writeFileChecked(const fs::path& file, std::string_view bytes) {
  const int fd = ::open(file.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_NOFOLLOW | O_CLOEXEC, 0666);
  if (fd < 0) failWrite(file, errno);
  for (std::size_t done = 0; done < bytes.size();) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int e = n < 0 ? errno : EIO;
      ::close(fd);
      failWrite(file, e);
    }
    done += std::size_t(n);
  }
  if (::close(fd) != 0) failWrite(file, errno);
}

void makeFolderChecked(const fs::path& folder) {
  if (::mkdir(folder.c_str(), 0777) != 0) failWrite(folder, errno);
}

void makeSymlinkChecked(const fs::path& points_to, const fs::path& link) {
  if (::symlink(points_to.c_str(), link.c_str()) != 0) failWrite(link, errno);
}
}  // namespace occsweep
