// Atomic outputs, refusal of existing ones, and removal of this process's temporaries on errors and signals
// (docs/robustness.md, "Outputs, temporaries and --force").
#include "occsweep/eval/output_file.hpp"
#include "occsweep/eval/interrupt_guard.hpp"
#include "occsweep/eval/bounded_read.hpp"
#include "occsweep/eval/ownership.hpp"

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <functional>
#include <map>
#include <mutex>
#include <set>
#include <streambuf>
#include <sys/stat.h>
#include <sys/wait.h>
#include <thread>
#include <utility>
#include <vector>
#include <unistd.h>

#include <nlohmann/json.hpp>

namespace occsweep {
namespace fs = std::filesystem;

namespace {

// ---- temporaries removed on SIGINT/SIGTERM/SIGHUP ----

// Never destroyed: the cleaning thread may still use them while static objects are destroyed at exit.
std::mutex& registryMutex() {
  static auto* m = new std::mutex;
  return *m;
}

}  // namespace

void runWithoutInterruptCleaning(const std::function<void()>& step) {
  const std::lock_guard lock(registryMutex());
  step();
}

namespace {

// The device and inode of the entry at `path` itself (not what a link there points to); {0, 0} when it cannot be read.
std::pair<dev_t, ino_t> entryNumbers(const fs::path& path) {
  struct stat st {};
  if (::lstat(path.c_str(), &st) != 0) return {0, 0};
  return {st.st_dev, st.st_ino};
}

// The live temporaries of this process, each with the entry it was made as: removed (on an error, an interrupt, or
// by its owner's destructor) only while that entry stands at its name. A user's entry is there for a moment when an
// exchange that put occsweep's output in place is being undone (a partial output's, sweep_partial.cpp), and is never
// occsweep's to remove.
std::map<fs::path, std::pair<dev_t, ino_t>>& liveTemporaries() {
  static auto* made = new std::map<fs::path, std::pair<dev_t, ino_t>>;
  return *made;
}

// Registers `path` and makes its entry (an empty file, opened for writing, or an empty folder) exclusively, in one
// step under the registry's lock, which an interrupt's cleaner holds until _exit (cleanOnInterrupt): the entry exists
// when the cleaner looks, and is removed, or is never made. Made after the lock is released, it could appear just
// after the cleaner's removal and outlive the exit. Returns the file's descriptor (0 for a folder); on failure, -1
// with errno set and nothing registered.
int registerAndCreate(const fs::path& path, TemporaryKind kind) {
  std::lock_guard lock(registryMutex());
  const int fd = kind == TemporaryKind::File
                     ? ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666)
                     : ::mkdir(path.c_str(), 0777);
  if (fd < 0) return fd;
  liveTemporaries()[path] = entryNumbers(path);
  return fd;
}

// Drops a temporary (removed, committed or kept) from the registry.
void unregisterTemporary(const fs::path& path) {
  std::lock_guard lock(registryMutex());
  liveTemporaries().erase(path);
}

// Whether the entry this run made as its temporary `path` still stands there: not when a user's entry is at its name
// (one exchanged there a moment ago, or put there while the run went on), nor once it was committed, kept or removed.
// Called under registryMutex.
bool madeEntryStands(const fs::path& path) {
  const auto made = liveTemporaries().find(path);
  return made != liveTemporaries().end() && made->second == entryNumbers(path);
}

// madeEntryStands, taking the lock.
bool isMadeEntry(const fs::path& path) {
  std::lock_guard lock(registryMutex());
  return madeEntryStands(path);
}

// What an interrupt prints before the exit (setInterruptMessage); read by the cleaner under the registry's lock.
std::string& interruptMessage() {
  static auto* message = new std::string;
  return *message;
}

// Children runChild waits for (child_process.hpp): ended before their temporaries are removed.
std::set<pid_t>& children() {
  static auto* pids = new std::set<pid_t>;
  return *pids;
}

int interrupt_pipe[2] = {-1, -1};

std::atomic<int> g_interrupt_signal{0};  // lock-free: written in the handler, read by other threads
static_assert(std::atomic<int>::is_always_lock_free);

// Async-signal-safe: a flag and write(2), errno kept for the interrupted code. The cleaning happens in an ordinary
// thread (cleanOnInterrupt).
extern "C" void forwardSignal(int sig) {
  const int saved_errno = errno;
  g_interrupt_signal.store(sig);
  const unsigned char byte = static_cast<unsigned char>(sig);
  [[maybe_unused]] const ssize_t n = ::write(interrupt_pipe[1], &byte, 1);
  errno = saved_errno;
}

// Writes `text` whole to stderr, as far as it goes.
void writeToStderr(const std::string& text) {
  for (std::size_t done = 0; done < text.size();) {
    const ssize_t n = ::write(2, text.data() + done, text.size() - done);
    if (n <= 0 && errno != EINTR) break;
    done += n > 0 ? std::size_t(n) : 0;
  }
}

// Removes every registered temporary, prints `message` and exits with `status`; the caller holds the registry's lock
// (cleanOnInterrupt, exitRemovingTemporaries).
[[noreturn]] void removeTemporariesAndExit(int status, const std::string& message) {
  // A child still writing (a figure script) would recreate a temporary removed under it: it ends first.
  for (const pid_t pid : children()) {
    ::kill(pid, SIGKILL);
    ::waitpid(pid, nullptr, 0);
  }
  for (const auto& [path, made] : liveTemporaries())
    if (made == entryNumbers(path)) removeTemporaryEntry(path);  // another entry at its name (or none) is a user's
  writeToStderr(message);
  ::_exit(status);
}

void cleanOnInterrupt() {
  unsigned char sig = 0;
  for (;;) {
    const ssize_t n = ::read(interrupt_pipe[0], &sig, 1);
    if (n == 1) break;
    if (n == 0 || errno != EINTR) return;  // the pipe is gone: no signal can be forwarded any more
  }
  // The lock is held until _exit: a commit (which takes it too) cannot rename a temporary into place after, or
  // while, its files are removed here (a SIGTERM'd `scene` once renamed a folder holding only manifest.json).
  registryMutex().lock();
  removeTemporariesAndExit(128 + sig, interruptMessage());
}

// ---- names ----

[[noreturn]] void fail(const fs::path& file, int error_number) { throw OutputError(writeFailure(file, error_number)); }

[[noreturn]] void fail(const fs::filesystem_error& e) {
  throw OutputError(writeFailure(e.path1().empty() ? fs::path("?") : e.path1(), e.code().value()));
}

void createParent(const fs::path& target) {
  if (!target.has_parent_path()) return;
  try {
    fs::create_directories(target.parent_path());
  } catch (const fs::filesystem_error& e) {
    fail(e);
  }
}

bool isEmptyFolder(const fs::path& p) {
  std::error_code ec;
  return fs::is_directory(fs::symlink_status(p, ec)) && fs::is_empty(p, ec);
}

// The name the user knows: a temporary `.NAME.tmp-PID-TOKEN` component shown as `NAME` (the output being written).
std::string userVisible(const fs::path& file) {
  fs::path shown;
  for (const auto& part : file) shown /= outputNameOf(part.string());
  return shown.string();
}

// ---- the target as the command checked it ----

}  // namespace

// What stood at an output's path: nothing, an empty folder (replaced, it holds nothing), or an entry named by its
// device, inode, size and modification time.
struct TargetState {
  bool exists = false, empty_folder = false;
  dev_t device = 0;
  ino_t inode = 0;
  off_t size = 0;
  timespec modified{};
  /// The kind's own check, kept when --force accepted the entry: run again on a folder swapped out at commit, whose
  /// deeper entries its top's time does not show.
  std::function<bool(const fs::path&)> is_own;
};

namespace {

TargetState stateOf(const fs::path& p) {
  struct stat st {};
  if (::lstat(p.c_str(), &st) != 0) return {};
  return {true, isEmptyFolder(p), st.st_dev, st.st_ino, st.st_size, st.st_mtim, {}};
}

bool sameEntry(const TargetState& a, const TargetState& b) {
  return a.device == b.device && a.inode == b.inode && a.size == b.size && a.modified.tv_sec == b.modified.tv_sec &&
         a.modified.tv_nsec == b.modified.tv_nsec;
}

fs::path targetKey(const fs::path& target) {
  std::error_code ec;
  const fs::path key = fs::weakly_canonical(fs::absolute(target, ec), ec);
  return ec ? fs::absolute(target, ec) : key;
}

// Targets checkOutputTarget accepted, as they were then (under registryMutex): a commit replaces no other state.
std::map<fs::path, TargetState>& checkedTargets() {
  static auto* targets = new std::map<fs::path, TargetState>;
  return *targets;
}

// A target no checkOutputTarget accepted is replaced by nothing: whatever stands there at the commit (a user's file
// written while occsweep ran, or before it) stays, and the commit fails naming it (docs/robustness.md, "Ownership").
TargetState checkedState(const fs::path& target) {
  std::lock_guard lock(registryMutex());
  const auto it = checkedTargets().find(targetKey(target));
  return it != checkedTargets().end() ? it->second : TargetState{};
}

[[noreturn]] void appeared(const fs::path& target, const char* what) {
  throw OutputConflict(userVisible(target) + ": " + what + " while occsweep was writing it: nothing was replaced " +
                    "(write to another path, or move it away and run again)");
}

// rename(2) that never replaces: an output created meanwhile stays (link-then-unlink where the file system has no
// RENAME_NOREPLACE; a folder there is renamed after the check, the one moment left open).
void renameNoReplace(const fs::path& from, const fs::path& to, bool folder) {
  if (::renameat2(AT_FDCWD, from.c_str(), AT_FDCWD, to.c_str(), RENAME_NOREPLACE) == 0) return;
  if (errno == EEXIST) appeared(to, "was created");
  if (errno != EINVAL && errno != ENOSYS) fail(to, errno);
  if (folder) {
    if (::rename(from.c_str(), to.c_str()) != 0) fail(to, errno);
  } else {
    if (::link(from.c_str(), to.c_str()) != 0) errno == EEXIST ? appeared(to, "was created") : fail(to, errno);
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
  liveTemporaries().erase(temporary);
  throw OutputConflict(userVisible(target) + ": was changed while occsweep was writing it, and could not be put " +
                       "back (" + std::strerror(e) + "): what stood there is now at " + temporary.string() +
                       ", occsweep's new output at " + userVisible(target) + "; occsweep removes neither");
}

void placeOutput(const fs::path& temporary, const fs::path& target, const TargetState& checked, bool folder) {
  // What the writer filled, not an entry put at the temporary's name meanwhile (renamed, it would be the output).
  if (liveTemporaries().contains(temporary) && !madeEntryStands(temporary))
    throw OutputConflict(temporary.string() + ": occsweep's temporary for " + userVisible(target) + " was replaced or " +
                         "removed while occsweep was writing it: nothing was committed, and what stands there is " +
                         "left as it is");
  const TargetState now = stateOf(target);
  std::error_code ec;
  requireAsChecked(target, checked, now);
  if (now.exists && !now.empty_folder) {
    if (!folder) {
      if (::rename(temporary.c_str(), target.c_str()) != 0) fail(target, errno);
      return;
    }
    // Swapped in one step: no moment without either the old or the new folder. The old one, now under the
    // registered temporary name, is removed only if every entry in it is still occsweep's; else swapped back.
    if (::renameat2(AT_FDCWD, temporary.c_str(), AT_FDCWD, target.c_str(), RENAME_EXCHANGE) == 0) {
      if (checked.is_own && !checked.is_own(temporary)) exchangeBack(temporary, target);
      fs::remove_all(temporary, ec);
      return;
    }
    if (errno != EINVAL && errno != ENOSYS) fail(target, errno);
    if (checked.is_own && !checked.is_own(target)) appeared(target, "was changed");
    fs::remove_all(target, ec);  // no RENAME_EXCHANGE on this file system
  } else if (now.empty_folder) {
    fs::remove(target, ec);  // an empty folder holds nothing of the user's
  }
  renameNoReplace(temporary, target, folder);
}

void recordCommitted(const fs::path& target) { checkedTargets()[targetKey(target)] = stateOf(target); }

}  // namespace

std::string writeFailure(const fs::path& file, int error_number) {
  const std::string name = userVisible(file);
  switch (error_number) {
    case ENOSPC: return name + ": no space left on device";
    case EDQUOT: return name + ": disk quota exceeded";
    case EFBIG: return name + ": file size limit exceeded (ulimit -f)";
    default: return name + ": cannot write: " + std::strerror(error_number);
  }
}

fs::path outputTarget(const fs::path& target) {
  fs::path p = target.lexically_normal();
  if (!p.has_filename() && p.has_parent_path()) p = p.parent_path();  // "s1/" is "s1"
  const std::string name = p.filename().string();
  if (p.empty() || name == "." || name == ".." || p.begin()->string() == "..") {
    p = (fs::current_path() / target).lexically_normal();
    if (!p.has_filename() && p != p.root_path()) p = p.parent_path();
  }
  return p;
}

ReplaceableOutput textOutput(const std::string& name, const std::string& first_line) {
  return {name, [first_line](const fs::path& file) {
            return notOwnReservedFile(file, first_line).empty() && holdsMarkedBytes(file);
          }};
}

std::vector<fs::path> missingFolders(const fs::path& dir) {
  std::vector<fs::path> missing;
  std::error_code ec;
  for (fs::path p = dir; !p.empty() && !fs::exists(fs::symlink_status(p, ec)); p = p.parent_path()) {
    missing.push_back(p);
    if (p == p.parent_path()) break;
  }
  return missing;
}

void removeEmptyFolders(const std::vector<fs::path>& folders) noexcept {
  std::error_code ec;
  for (const fs::path& p : folders) fs::remove(p, ec);  // refuses a folder that is not empty
}

ReplaceableOutput jsonOutput(const std::string& name, const std::string& format) {
  return {name, [format](const fs::path& file) {
            std::error_code ec;
            if (!fs::is_regular_file(fs::symlink_status(file, ec))) return false;
            return jsonFormatField(file) == format;  // its first bytes: a file of gigabytes is never read whole
          }};
}

namespace {
void requireOneReading(const fs::path& output);
}  // namespace

void checkOutputTarget(const fs::path& target, bool force, const ReplaceableOutput& kind) {
  requireOneReading(target);
  const fs::path t = outputTarget(target);
  std::error_code ec;
  const fs::path here = fs::weakly_canonical(fs::current_path(), ec), there = fs::weakly_canonical(t, ec);
  const auto [mismatch, _] = std::mismatch(there.begin(), there.end(), here.begin(), here.end());
  if (!there.empty() && mismatch == there.end())
    throw OutputError(target.string() + ": is the current folder or holds it: choose a new folder for the " +
                      kind.name);
  // A link is the user's entry whatever it points to: replacing it would drop their link, writing through it would
  // write elsewhere (docs/robustness.md, "Ownership").
  if (fs::is_symlink(fs::symlink_status(t, ec)))
    throw OutputError(target.string() + ": is a symbolic link: occsweep never writes through or replaces one, even "
                      "with --force (nothing was changed); give the path it points to, or choose another path");
  // A FIFO, socket or device is no one's output, and reading it for occsweep's mark would wait for ever on a FIFO:
  // refused at once, named by what it is (docs/robustness.md, "Limits and non-regular files").
  if (fs::is_other(fs::symlink_status(t, ec))) requireRegularFile(t);
  TargetState state = stateOf(t);
  if (state.exists && !state.empty_folder) {
    if (!force)
      throw OutputError(target.string() + ": exists: occsweep replaces nothing unless asked (--force replaces " +
                        "occsweep's own previous " + kind.name + "; or choose another path)");
    // A second name (a hard link) is the user's hold on these bytes, as a symbolic link is ("Ownership").
    if (struct stat st {}; ::lstat(t.c_str(), &st) == 0 && S_ISREG(st.st_mode) && st.st_nlink != 1)
      throw OutputError(target.string() + ": has " + std::to_string(st.st_nlink) + " names (a hard link): occsweep " +
                        "never replaces a file another name shares, even with --force (nothing was changed); remove " +
                        "the other name, or choose another path");
    if (!kind.is_own(t))
      throw OutputError(target.string() + ": exists and is not occsweep's " + kind.name +
                        ": refused even with --force (nothing was changed)");
    state.is_own = kind.is_own;
  }
  std::lock_guard lock(registryMutex());
  checkedTargets()[targetKey(t)] = state;  // the state a commit may replace (placeOutput)
}

namespace {

// An output as the writer reads it, and as the system resolves it ("link/.." is the link target's parent).
struct OutputReadings {
  fs::path lexical, resolved;
};

OutputReadings outputReadings(const fs::path& output) {
  auto dropTrailingSlash = [](fs::path p) { return p.has_filename() ? p : p.parent_path(); };
  const fs::path lexical = dropTrailingSlash(fs::absolute(output).lexically_normal());
  std::error_code ec;
  const fs::path resolved = dropTrailingSlash(fs::weakly_canonical(fs::absolute(output), ec));
  return {lexical, ec ? lexical : resolved};
}

// An output whose ".." follows a symbolic link reads two ways: the writer's (lexical: "link/.." is the link's own
// folder) and the system's ("link/.." is the link target's parent). Every check and the write must mean one file,
// so such a path is refused (docs/robustness.md, "Ownership").
void requireOneReading(const fs::path& output) {
  const OutputReadings r = outputReadings(output);
  std::error_code ec;
  const fs::path lexical_resolved = fs::weakly_canonical(r.lexical, ec);
  if (ec || lexical_resolved == r.resolved) return;
  throw OutputError(output.string() + ": '..' after a symbolic link names " + r.resolved.string() +
                    " to the system but " + lexical_resolved.string() +
                    " read as written: give the path without '..' (nothing was changed)");
}

// `inner` is `outer` or lies under it.
bool within(const fs::path& inner, const fs::path& outer) {
  return std::mismatch(outer.begin(), outer.end(), inner.begin(), inner.end()).first == outer.end();
}

// The existing entry that blocks the path to `output`: a file or a broken link where a folder must be (the writer
// makes missing folders, but none under a file or through a broken link); empty when none does.
fs::path blockingEntry(const fs::path& output) {
  std::error_code ec;
  for (fs::path p = outputReadings(output).lexical.parent_path(); !p.empty(); p = p.parent_path()) {
    if (fs::symlink_status(p, ec).type() != fs::file_type::not_found) return fs::is_directory(p, ec) ? fs::path() : p;
    if (p == p.parent_path()) break;
  }
  return {};
}

}  // namespace

void requireCompanionName(const fs::path& target, const std::string& suffix) {
  const std::string name = outputTarget(target).filename().string();
  if (name.size() + suffix.size() <= kFileNameMax) return;
  throw OutputError(target.string() + ": a name of " + std::to_string(name.size()) + " bytes leaves no room for its " +
                    "companion NAME" + suffix + " (a file name has at most 255 bytes): choose a name of at most " +
                    std::to_string(kFileNameMax - suffix.size()) + " bytes");
}

namespace {
// One name in one existing folder, by the folder's identity (device and inode): two spellings of a folder that no
// path comparison sees as one (a bind mount) still name one file.
bool sameNameInSameFolder(const OutputReadings& a, const OutputReadings& b) {
  if (a.resolved.filename() != b.resolved.filename()) return false;
  struct stat fa {}, fb {};
  if (::stat(a.resolved.parent_path().c_str(), &fa) != 0 || ::stat(b.resolved.parent_path().c_str(), &fb) != 0)
    return false;
  return fa.st_dev == fb.st_dev && fa.st_ino == fb.st_ino;
}
}  // namespace

bool outputsCollide(const fs::path& a, const fs::path& b) {
  const OutputReadings ra = outputReadings(a), rb = outputReadings(b);
  for (const auto& [x, y] : {std::pair{ra.lexical, rb.lexical}, {ra.resolved, rb.resolved}})
    if (within(x, y) || within(y, x)) return true;
  return sameNameInSameFolder(ra, rb);
}

void requireSeparateOutputs(const std::vector<std::pair<std::string, fs::path>>& outputs) {
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    const auto& [flag, path] = outputs[i];
    if (path.empty()) continue;
    requireOneReading(path);
    if (const fs::path entry = blockingEntry(path); !entry.empty())
      throw OutputError(flag + " " + path.string() + ": " + entry.string() + " is not a folder");
    for (std::size_t j = i + 1; j < outputs.size(); ++j)
      if (!outputs[j].second.empty() && outputsCollide(path, outputs[j].second))
        throw OutputError(flag + " and " + outputs[j].first + " name one file, or one lies under the other (" +
                          path.string() + ", " + outputs[j].second.string() + "): each output needs a file of its own");
  }
}

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

OutputFile::OutputFile(const fs::path& target) : target_(outputTarget(target)) {
  createParent(target_);
  reportLeftoverTemporaries(target_);
  checked_ = std::make_unique<TargetState>(checkedState(target_));
  temporary_ = temporaryNameFor(target_);
  const int fd = registerAndCreate(temporary_, TemporaryKind::File);
  if (fd < 0) fail(target_, errno);
  buffer_ = std::make_unique<Buffer>(fd);
  stream_ = std::make_unique<std::ostream>(buffer_.get());
}

OutputFile::~OutputFile() {
  if (buffer_ && buffer_->fd >= 0) ::close(buffer_->fd);
  if (!committed_ && isMadeEntry(temporary_)) {
    std::error_code ec;
    fs::remove(temporary_, ec);
  }
  unregisterTemporary(temporary_);
}

std::ostream& OutputFile::stream() { return *stream_; }

void OutputFile::finish() {
  if (buffer_->fd < 0) return;
  stream_->flush();
  if (buffer_->error != 0 || !*stream_) fail(target_, buffer_->error != 0 ? buffer_->error : EIO);
  // fsync: a rename is only as durable as the data it points at (a crash right after it must not leave zeros).
  if (::fsync(buffer_->fd) != 0 && errno != EINVAL) fail(target_, errno);
  const int fd = buffer_->fd;
  buffer_->fd = -1;
  if (::close(fd) != 0) fail(target_, errno);
}

void OutputFile::markWritten() {
  finish();
  markWrittenBytes(temporary_);
}

void OutputFile::commit() { commitTogether({this}); }

void OutputFile::commitTogether(const std::vector<OutputFile*>& files) {
  for (OutputFile* f : files) f->finish();  // every write checked before any rename
  std::unique_lock lock(registryMutex());    // no rename once an interrupt's cleaning has begun (cleanOnInterrupt)
  for (OutputFile* f : files) requireAsChecked(f->target_, *f->checked_, stateOf(f->target_));
  for (OutputFile* f : files) {
    placeOutput(f->temporary_, f->target_, *f->checked_, false);
    recordCommitted(f->target_);
    f->committed_ = true;
  }
}

// ---- OutputFolder ----

OutputFolder::OutputFolder(const fs::path& target) : target_(outputTarget(target)) {
  createParent(target_);
  reportLeftoverTemporaries(target_);
  checked_ = std::make_unique<TargetState>(checkedState(target_));
  temporary_ = temporaryNameFor(target_);
  if (registerAndCreate(temporary_, TemporaryKind::Folder) != 0) fail(target_, errno);
}

OutputFolder::~OutputFolder() {
  if (!committed_ && isMadeEntry(temporary_)) {  // not one exchangeBack left holding a user's folder
    std::error_code ec;
    fs::remove_all(temporary_, ec);
  }
  unregisterTemporary(temporary_);
}

void OutputFolder::commit() {
  std::unique_lock lock(registryMutex());  // no rename once an interrupt's cleaning has begun (cleanOnInterrupt)
  placeOutput(temporary_, target_, *checked_, true);
  recordCommitted(target_);
  committed_ = true;
}

// ---- ClaimedTemporary ----

ClaimedTemporary::ClaimedTemporary(const fs::path& target, TemporaryKind kind) {
  const fs::path t = outputTarget(target);
  reportLeftoverTemporaries(t);
  path_ = temporaryNameFor(t);
  const int fd = registerAndCreate(path_, kind);
  if (fd < 0) fail(t, errno);
  if (kind == TemporaryKind::File) ::close(fd);
}

ClaimedTemporary::~ClaimedTemporary() {
  if (!kept_ && isMadeEntry(path_)) removeTemporaryEntry(path_);
  unregisterTemporary(path_);
}

void ClaimedTemporary::keep() {
  unregisterTemporary(path_);
  kept_ = true;
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
  if (fd < 0) fail(file, errno);
  for (std::size_t done = 0; done < bytes.size();) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int e = n < 0 ? errno : EIO;
      ::close(fd);
      fail(file, e);
    }
    done += std::size_t(n);
  }
  if (::close(fd) != 0) fail(file, errno);
}

void makeFolderChecked(const fs::path& folder) {
  if (::mkdir(folder.c_str(), 0777) != 0) fail(folder, errno);
}

void makeSymlinkChecked(const fs::path& points_to, const fs::path& link) {
  if (::symlink(points_to.c_str(), link.c_str()) != 0) fail(link, errno);
}

void setInterruptMessage(std::string message) {
  std::lock_guard lock(registryMutex());
  interruptMessage() = std::move(message);
}

int interruptSignalReceived() { return g_interrupt_signal.load(); }

void exitRemovingTemporaries(int status, const std::string& message) {
  // A thread that failed holding the lock (this one, inside a commit) never releases it: after a second the exit
  // leaves the temporaries to the next run, as a SIGKILL does (removeStaleTemporaries).
  for (int waited_ms = 0; !registryMutex().try_lock(); waited_ms += 10) {
    if (waited_ms >= 1000) {
      writeToStderr(message);
      ::_exit(status);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  removeTemporariesAndExit(status, message);
}

pid_t forkRegisteredChild() {
  // Under the registry's lock, which the interrupt cleaner takes first: it either sees the child, or has begun
  // and this process is about to exit (no child is started then).
  std::lock_guard lock(registryMutex());
  if (interruptSignalReceived() != 0) return -1;
  const pid_t pid = ::fork();
  if (pid > 0) children().insert(pid);
  return pid;
}

void unregisterChildProcess(pid_t pid) {
  std::lock_guard lock(registryMutex());
  children().erase(pid);
}

void removeTemporariesOnInterrupt() {
  static std::once_flag once;
  std::call_once(once, [] {
    if (::pipe2(interrupt_pipe, O_CLOEXEC) != 0) return;
    std::thread(cleanOnInterrupt).detach();
    struct sigaction action {};
    action.sa_handler = forwardSignal;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESTART;
    for (int sig : {SIGINT, SIGTERM, SIGHUP}) ::sigaction(sig, &action, nullptr);
    std::signal(SIGXFSZ, SIG_IGN);  // past `ulimit -f`, write(2) fails with EFBIG: a message instead of a core
  });
}

}  // namespace occsweep
