// The partial log of a sweep: what a killed sweep resumes from; and the lock every partial output is held by.
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <fstream>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <optional>

#include "occsweep/eval/bounded_read.hpp"
#include "occsweep/sweeps/results_verify.hpp"
#include "sweep_internal.hpp"

namespace occsweep::sweep_detail {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

[[noreturn]] void anotherWriter(const fs::path& file) {
  throw std::runtime_error("another occsweep is writing " + file.string() +
                           " (a sweep into the same --out is running: wait for it to finish, or choose another --out)");
}

[[noreturn]] void partialReplacedMeanwhile(const fs::path& file) {
  throw std::runtime_error(file.string() + ": was replaced while occsweep was preparing the sweep; what stands at "
                           "its name now is left as it is (docs/robustness.md, \"Ownership\")");
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

// The header line of a partial log (nothing when the file has none that parses).
std::optional<ResultsHeader> logHeader(const fs::path& partial) {
  constexpr std::size_t kMaxHeaderLine = 1 << 20;  // a header line is a few kB: a user's huge file is not read whole
  const std::optional<std::string> line = readFirstLine(partial, kMaxHeaderLine);
  if (!line) return std::nullopt;
  try {
    return parseHeader(json::parse(*line), partial.string());
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

// The header of occsweep's partial log at `partial`. occsweep writes it before the log appears under its name
// (PartialLock::publish): a file without one is not occsweep's, and is never replaced (docs/robustness.md, "Outputs,
// temporaries and --force").
ResultsHeader ownLogHeader(const fs::path& partial, const PartialLock& lock) {
  std::optional<ResultsHeader> header = logHeader(lock.heldFilePath());
  if (!header)
    throw std::runtime_error(partial.string() + ": not a partial log of occsweep's (its first line is not a sweep's "
                             "header); occsweep never replaces or removes it (even with --force): remove it, or choose "
                             "another --out");
  return std::move(*header);
}

}  // namespace

PartialLock::~PartialLock() {
  if (fd_ >= 0) ::close(fd_);
}

PartialLock& PartialLock::operator=(PartialLock&& o) noexcept {
  if (this != &o) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = std::exchange(o.fd_, -1);
  }
  return *this;
}

PartialLock PartialLock::existing(const fs::path& file) {
  requireOwnablePartial(file);
  PartialLock lock(lockedDescriptor(file));
  struct stat held {}, now {};
  // The writer that held it may have renamed it into place meanwhile: the lock is then on another file.
  if (!lock.held() || ::fstat(lock.fd_, &held) != 0 || ::lstat(file.c_str(), &now) != 0 || held.st_ino != now.st_ino ||
      held.st_dev != now.st_dev)
    anotherWriter(file);
  return lock;
}

namespace {

// The user's file, exchanged to the temporary's name, back at `file`: by a second exchange, else by a rename over the
// sweep's own new file (which `made` proves is what stands at `file`). Where both fail it stays at the temporary's
// name, kept and named: never removed as the sweep's.
[[noreturn]] void putBackUsersFile(ClaimedTemporary& claimed, const fs::path& file, const PartialLock& made) {
  const fs::path& temporary = claimed.path();
  if (::renameat2(AT_FDCWD, temporary.c_str(), AT_FDCWD, file.c_str(), RENAME_EXCHANGE) == 0)
    partialReplacedMeanwhile(file);
  std::string why = std::string("exchange: ") + std::strerror(errno);
  const bool sweeps_at_name = made.holdsFile(file);
  if (sweeps_at_name && ::rename(temporary.c_str(), file.c_str()) == 0) partialReplacedMeanwhile(file);
  why += sweeps_at_name ? std::string("; rename: ") + std::strerror(errno) : "; another file stands at its name now";
  claimed.keep();
  throw std::runtime_error(file.string() + ": was replaced while occsweep was preparing the sweep, and could not be "
                           "put back (" + why + "): the file that stood there is now at " + temporary.string() +
                           ", which occsweep never removes" +
                           (sweeps_at_name ? "; the sweep's new partial output is at " + file.string() : ""));
}

// Puts the sweep's new partial output (`claimed`, locked by `made`) at `file` in place of the one `replacing` holds,
// and removes that one. Exchanged atomically, then checked: a file a user put at the name meanwhile (the sweep
// prepared its data for minutes) goes back, and the sweep stops naming it.
void replaceHeldPartial(ClaimedTemporary& claimed, const fs::path& file, const PartialLock& replacing,
                        const PartialLock& made) {
  const fs::path& temporary = claimed.path();
  if (::renameat2(AT_FDCWD, temporary.c_str(), AT_FDCWD, file.c_str(), RENAME_EXCHANGE) != 0) {
    if (errno != EINVAL && errno != ENOSYS)
      throw std::runtime_error(file.string() + ": cannot replace (" + std::strerror(errno) + ")");
    if (!replacing.holdsFile(file)) partialReplacedMeanwhile(file);  // no exchange on this file system
    fs::rename(temporary, file);
    return;
  }
  if (!replacing.holdsFile(temporary)) putBackUsersFile(claimed, file, made);
  replacing.removeHeldFile(temporary);  // the old partial output, now at the temporary's name
}

}  // namespace

PartialLock PartialLock::publish(const fs::path& file, const PartialLock* replacing,
                                 const std::function<void(const fs::path&)>& make) {
  // Claimed and registered as OutputFile's temporaries are (docs/robustness.md, "Ownership"): an interrupt removes
  // it while it is the file made there, and what a kill leaves the next run removes. A user's file is at that name
  // only while an exchange is undone (putBackUsersFile), or once kept.
  // Its destructor removes the temporary's name, and only while it names the file made there.
  ClaimedTemporary claimed(file, TemporaryKind::File);  // `make` fills it, never creates it
  const fs::path& temporary = claimed.path();
  make(temporary);
  PartialLock lock(lockedDescriptor(temporary));
  // Locked before it appears under its name: a second sweep finds it locked. link() never replaces a file.
  if (replacing) replaceHeldPartial(claimed, file, *replacing, lock);
  else if (::link(temporary.c_str(), file.c_str()) != 0) {
    if (errno == EEXIST) anotherWriter(file);
    throw std::runtime_error(file.string() + ": cannot create (" + std::strerror(errno) + ")");
  }
  return lock;
}

void requireOwnablePartial(const fs::path& file) {
  std::error_code ec;
  if (fs::is_symlink(fs::symlink_status(file, ec)))
    throw std::runtime_error(file.string() + ": a symbolic link where the sweep keeps its partial output; occsweep "
                             "never writes through, replaces or removes it (even with --force): remove it, or choose "
                             "another --out");
  requireRegularFile(file);  // a FIFO would block the sweep
}

bool isOwnPartialLog(const fs::path& partial, const ResultsHeader& header) {
  std::error_code ec;
  if (!fs::is_regular_file(fs::symlink_status(partial, ec))) return false;
  const std::optional<ResultsHeader> old = logHeader(partial);
  return old && sameWork(*old, header, true, nullptr);
}

std::map<std::uint64_t, MapResult> loadPartial(const fs::path& partial, const ResultsHeader& header, bool force,
                                               std::map<std::uint64_t, std::string>& engine_of,
                                               std::map<std::uint64_t, MapResult>* twin, PartialLock& lock) {
  std::map<std::uint64_t, MapResult> done;
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(partial, ec))) return done;
  lock = PartialLock::existing(partial);
  const ResultsHeader old = ownLogHeader(partial, lock);
  std::ifstream in(lock.heldFilePath());  // the file locked, whatever is put at its name meanwhile
  std::string line;
  std::getline(in, line);
  std::string why;
  if (!sameWork(old, header, true, &why)) {
    if (force) return done;  // occsweep's of other work: replaced when the log starts
    throw std::runtime_error(partial.string() + ": an interrupted sweep of other work (" + why +
                             "); --force replaces it, or choose another --out");
  }
  while (std::getline(in, line)) {
    try {
      const json j = json::parse(line);
      MapResult m = parseMapResult(j, header.parameters, partial.string(), "line");
      if (twin) {
        json t = j;  // the same map with the twin's thresholds and AUC, checked as strictly
        t["thresholds"] = j.at(kTwinField).at("thresholds");
        t["auc"] = j.at(kTwinField).at("auc");
        (*twin)[m.map_index] = parseMapResult(t, header.parameters, partial.string(), "line");
      }
      // Lines written before maps recorded their engine were made by the engine of the header's run.
      engine_of[m.map_index] = j.is_object() && j.contains("engine") ? j.at("engine").get<std::string>() : old.engine;
      done[m.map_index] = std::move(m);
    } catch (const std::exception&) {
    }
  }
  return done;
}

PartialLog::PartialLog(fs::path file, const ResultsHeader& header, std::size_t maps_done, PartialLock lock)
    : file_(std::move(file)), lock_(std::move(lock)), maps_(maps_done) {
  if (maps_done == 0) {
    // The header is written before the log appears under its name: a log without it is never occsweep's.
    lock_ = PartialLock::publish(file_, lock_.held() ? &lock_ : nullptr, [&](const fs::path& temporary) {
      std::ofstream first(temporary, std::ios::in | std::ios::out);  // the claimed empty file; never created here
      first << toJson(header).dump() << '\n' << std::flush;
      if (!first) throw OutputError(writeFailure(file_, errno));
    });
  }
  out_.open(lock_.heldFilePath(), std::ios::app);  // never by name: a file put there meanwhile is a user's
  if (!out_) {
    OutputError error = writeFailed();
    removeUnlessResumable();  // the destructor does not run for a constructor that throws
    throw error;
  }
}

PartialLog::~PartialLog() { removeUnlessResumable(); }

void PartialLog::append(const json& line) {
  std::lock_guard lock(mutex_);
  out_ << line.dump() << '\n' << std::flush;
  if (!out_) throw writeFailed();
  ++maps_;
}

bool PartialLock::holdsFile(const fs::path& file) const noexcept {
  struct stat held {}, now {};
  if (fd_ < 0 || ::fstat(fd_, &held) != 0 || ::lstat(file.c_str(), &now) != 0) return false;
  return held.st_dev == now.st_dev && held.st_ino == now.st_ino;
}

void PartialLock::removeHeldFile(const fs::path& file) const noexcept {
  if (holdsFile(file)) ::unlink(file.c_str());
}

fs::path PartialLock::heldFilePath() const {
  if (fd_ < 0) throw std::logic_error("PartialLock::heldFilePath: no file held");
  return fs::path("/proc/self/fd") / std::to_string(fd_);
}

void PartialLog::remove() {
  out_.close();
  lock_.removeHeldFile(file_);
}

OutputError PartialLog::writeFailed() {
  write_failed_ = true;
  return OutputError(writeFailure(file_, errno));
}

void PartialLog::removeUnlessResumable() noexcept {
  if (maps_ == 0 || write_failed_) lock_.removeHeldFile(file_);
}

bool completeResultsOf(const fs::path& file, const ResultsHeader& header) {
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(file, ec))) return false;
  checkOutputTarget(file, true, resultsOutput());
  try {
    // Checked and read in one pass: reused only when it passes every check of `results check` (an incomplete or
    // edited twin throws, and is swept anew).
    const ResultsFile f = readCheckedResults(file, MapDetail::Full);
    return f.complete && sameWork(f.header, header, true, nullptr);
  } catch (const std::exception&) {
    return false;  // occsweep's own but unreadable: replaced
  }
}

}  // namespace occsweep::sweep_detail
