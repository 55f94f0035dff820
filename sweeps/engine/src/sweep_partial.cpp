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
#include "occsweep/eval/interrupt_guard.hpp"
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

// The header of occsweep's partial log at `partial`, held by `lock` (a regular file with one name:
// PartialLock::existing). A file at that reserved name whose first line is not a sweep's header is a user's: never
// resumed from, replaced or removed (docs/robustness.md, "Ownership").
ResultsHeader ownLogHeader(const fs::path& partial, const PartialLock& lock) {
  std::optional<ResultsHeader> header = logHeader(lock.heldFilePath());
  if (!header)
    throw std::runtime_error(partial.string() + ": not a partial log of occsweep's (its first line is not a sweep's "
                             "header); occsweep never resumes from, replaces or removes it (even with --force): remove "
                             "it, or choose another --out");
  return std::move(*header);
}

// Removes occsweep's log at `partial` while it is the file `lock` holds.
void removeOwnLog(const fs::path& partial, const PartialLock& lock) { lock.removeHeldFile(partial); }

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
  // A second name (a hard link a user made) would be written through as a symbolic link would (docs/robustness.md).
  if (held.st_nlink != 1)
    throw std::runtime_error(file.string() + ": has " + std::to_string(held.st_nlink) + " names (a hard link); "
                             "occsweep never writes into, replaces or removes a partial output that has another name "
                             "(even with --force): remove the other name, or choose another --out");
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
  bool users_file_exchanged = false;
  runWithoutInterruptCleaning([&] {
    if (::renameat2(AT_FDCWD, temporary.c_str(), AT_FDCWD, file.c_str(), RENAME_EXCHANGE) != 0) {
      if (errno != EINVAL && errno != ENOSYS)
        throw std::runtime_error(file.string() + ": cannot replace (" + std::strerror(errno) + ")");
      if (!replacing.holdsFile(file)) partialReplacedMeanwhile(file);  // no exchange on this file system
      fs::rename(temporary, file);
    } else if (!replacing.holdsFile(temporary)) {
      users_file_exchanged = true;
      return;
    }
    replacing.removeHeldFile(temporary);  // the old partial output, now at the temporary's name (if exchanged)
  });
  if (users_file_exchanged) putBackUsersFile(claimed, file, made);
}

}  // namespace

PartialLock PartialLock::publish(const fs::path& file, const PartialLock* replacing,
                                 const std::function<void(const fs::path&)>& make) {
  // Made and registered as OutputFile's temporaries are (docs/robustness.md, "Ownership"): an interrupt removes
  // it while it is the file made there; what a kill leaves the next run names. A user's file is at that name only
  // while an exchange is undone (putBackUsersFile), or once kept.
  // Its destructor removes the temporary's name, and only while it names the file made there.
  ClaimedTemporary claimed(file, TemporaryKind::File);  // `make` fills it, never creates it
  const fs::path& temporary = claimed.path();
  make(temporary);
  PartialLock lock(lockedDescriptor(temporary));
  // Locked before it appears under its name: a second sweep finds it locked. Neither the exchange nor the rename
  // below replaces a file.
  if (replacing) {
    replaceHeldPartial(claimed, file, *replacing, lock);
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

void requireOwnablePartial(const fs::path& file) {
  std::error_code ec;
  if (fs::is_symlink(fs::symlink_status(file, ec)))
    throw std::runtime_error(file.string() + ": a symbolic link where the sweep keeps its partial output; occsweep "
                             "never writes through, replaces or removes it (even with --force): remove it, or choose "
                             "another --out");
  requireRegularFile(file);  // a FIFO would block the sweep
}

namespace {

// A whole map line of the log as JSON. Every line occsweep writes is JSON: one that is not was written into the log
// by someone else, and the log is no longer occsweep's alone.
json loggedLine(const std::string& line, const fs::path& partial, std::size_t number) {
  try {
    return json::parse(line);
  } catch (const json::exception&) {
    throw std::runtime_error(partial.string() + ": line " + std::to_string(number) + " is not a line occsweep "
                             "wrote (bytes were written into the log); occsweep never resumes from, replaces or "
                             "removes it (even with --force): remove it, or choose another --out");
  }
}

[[noreturn]] void notOwnLine(const fs::path& partial, std::size_t number, const std::string& why) {
  throw std::runtime_error(partial.string() + ": line " + std::to_string(number) + " is not a map line occsweep " +
                           "wrote (" + why + "); occsweep never resumes from, replaces or removes it (even with " +
                           "--force): remove it, or choose another --out");
}

// A whole line's map (and the twin's counts of it) into `done`. A line that is no map was written by someone else;
// a map of no use to this run (without the twin's counts) is left out: it is counted again.
void takeLoggedMap(const json& j, std::size_t number, const fs::path& partial, const ResultsHeader& header,
                   const std::string& old_engine, std::map<std::uint64_t, MapResult>& done,
                   std::map<std::uint64_t, std::string>& engine_of, std::map<std::uint64_t, MapResult>* twin) {
  MapResult m;
  try {
    m = parseMapResult(j, header.parameters, partial.string(), "line");
  } catch (const std::exception& e) {
    notOwnLine(partial, number, e.what());
  }
  try {
    if (twin) {
      json t = j;  // the same map with the twin's thresholds and AUC, checked as strictly
      t["thresholds"] = j.at(kTwinField).at("thresholds");
      t["auc"] = j.at(kTwinField).at("auc");
      (*twin)[m.map_index] = parseMapResult(t, header.parameters, partial.string(), "line");
    }
    // Lines written before maps recorded their engine were made by the engine of the header's run.
    engine_of[m.map_index] = j.is_object() && j.contains("engine") ? j.at("engine").get<std::string>() : old_engine;
    done[m.map_index] = std::move(m);
  } catch (const std::exception&) {
  }
}

// Cuts the log held by `lock` at `whole`, the end of its last line with a line break: what a kill cut off a line
// goes, so that the next line starts on a line of its own.
void dropCutLine(const fs::path& partial, const PartialLock& lock, std::uintmax_t whole) {
  if (::truncate(lock.heldFilePath().c_str(), off_t(whole)) != 0)
    throw std::runtime_error(partial.string() + ": cannot drop the line a kill cut (" + std::strerror(errno) + ")");
}

// The end of a log's last whole line, and whether a line after it was cut (only a kill cuts a line, and only the
// last, before its line break).
struct LogEnd {
  std::uintmax_t whole = 0;
  bool cut = false;
};

// Reads every map line of the log `lock` holds, after its header, each passed to `take` when given. Every whole line
// must be JSON: one that is not was written into the log by someone else, and the log is not replaced or removed.
LogEnd readLogLines(const fs::path& partial, const PartialLock& lock,
                    const std::function<void(const json&, std::size_t)>& take) {
  std::ifstream in(lock.heldFilePath());  // the file locked, whatever is put at its name meanwhile
  std::string line;
  std::getline(in, line);
  LogEnd end{std::uintmax_t(in.tellg()), false};
  for (std::size_t number = 2; std::getline(in, line); ++number) {
    if (in.eof()) {  // a cut line: its map is counted again
      end.cut = true;
      break;
    }
    end.whole += line.size() + 1;
    const json j = loggedLine(line, partial, number);
    if (take) take(j, number);
  }
  return end;
}

// Every resumed map is one of this sweep's grid, with its own parameters and ids, and all count one region, as
// `results check` verifies (ClaimsChecker, GridChecker): a line copied into the log from another map or another
// sweep is refused, never written into results.
void requireMapsOfThisSweep(const fs::path& partial, const ResultsHeader& header,
                            const std::map<std::uint64_t, MapResult>& done) {
  try {
    ClaimsChecker claims(header, false, partial.string());
    GridChecker grid(header, false, partial.string());
    for (const auto& [index, m] : done) {
      claims.add(m);
      grid.add(m);
    }
  } catch (const std::exception& e) {
    throw std::runtime_error(std::string(e.what()) + ": not the maps occsweep wrote for this sweep; occsweep never " +
                             "resumes from, replaces or removes this partial log (even with --force): remove it, or " +
                             "choose another --out");
  }
}

}  // namespace

void removeSupersededLog(const fs::path& partial, const ResultsHeader& header) {
  std::error_code ec;
  if (!fs::is_regular_file(fs::symlink_status(partial, ec))) return;
  try {
    const PartialLock lock = PartialLock::existing(partial);  // never while another sweep writes it
    if (!sameWork(ownLogHeader(partial, lock), header, true, nullptr)) return;
    (void)readLogLines(partial, lock, {});  // only what occsweep wrote
    removeOwnLog(partial, lock);
  } catch (const std::exception&) {  // another sweep writes it, it is not occsweep's, or it cannot be read: left
  }
}

std::map<std::uint64_t, MapResult> loadPartial(const fs::path& partial, const ResultsHeader& header, bool force,
                                               std::map<std::uint64_t, std::string>& engine_of,
                                               std::map<std::uint64_t, MapResult>* twin, PartialLock& lock) {
  std::map<std::uint64_t, MapResult> done;
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(partial, ec))) return done;
  lock = PartialLock::existing(partial);
  const ResultsHeader old = ownLogHeader(partial, lock);
  std::string why;
  const bool same = sameWork(old, header, true, &why);
  const LogEnd end = readLogLines(partial, lock, [&](const json& j, std::size_t number) {
    if (same) takeLoggedMap(j, number, partial, header, old.engine, done, engine_of, twin);
  });
  if (!same) {
    if (force) return done;  // occsweep's of other work: replaced when the log starts
    throw std::runtime_error(partial.string() + ": an interrupted sweep of other work (" + why +
                             "); --force replaces it, or choose another --out");
  }
  requireMapsOfThisSweep(partial, header, done);
  if (end.cut) dropCutLine(partial, lock, end.whole);  // the next line then starts on a line of its own
  return done;
}

PartialLog::PartialLog(fs::path file, const ResultsHeader& header, std::size_t maps_done, PartialLock lock)
    : file_(std::move(file)), lock_(std::move(lock)), maps_(maps_done) {
  if (maps_done == 0) {
    // The header is written before the log appears under its name: a log without it is never occsweep's.
    lock_ = PartialLock::publish(file_, lock_.held() ? &lock_ : nullptr, [&](const fs::path& temporary) {
      std::ofstream first(temporary, std::ios::in | std::ios::out);  // the made empty file; never created here
      first << toJson(header).dump() << '\n' << std::flush;
      if (!first) throw OutputError(writeFailure(file_, errno));
    });
  }
  struct stat held {};
  if (::fstat(lock_.descriptor(), &held) != 0) throw OutputError(writeFailure(file_, errno));
  whole_bytes_ = std::uintmax_t(held.st_size);
  out_.open(lock_.heldFilePath(), std::ios::app);  // never by name: a file put there meanwhile is a user's
  if (!out_) {
    const OutputError error(writeFailure(file_, errno));
    removeUnlessResumable();  // the destructor does not run for a constructor that throws
    throw error;
  }
}

PartialLog::~PartialLog() { removeUnlessResumable(); }

void PartialLog::append(const json& line) {
  std::lock_guard lock(mutex_);
  if (failed_) throw OutputError(failure_);
  const std::string text = line.dump() + '\n';
  bool written = false;
  int error_number = 0;
  runWithoutInterruptCleaning([&] {  // whole or not at all when an interrupt comes
    out_ << text << std::flush;
    written = bool(out_);
    if (written) whole_bytes_ += text.size();
    else error_number = errno;
  });
  if (!written) {
    failed_ = true;
    out_.close();  // what it still holds is dropped below
    // What a full disk cut off the last line goes: the log ends with its last whole map (docs/robustness.md).
    const bool cut = ::truncate(lock_.heldFilePath().c_str(), off_t(whole_bytes_)) == 0;
    failure_ = writeFailure(file_, error_number) + (cut ? keptNote() : "; the partial log could not be cut back");
    throw OutputError(failure_);
  }
  ++maps_;
}

std::string PartialLog::keptNote() const {
  if (maps_ == 0) return "";
  return "; the " + std::to_string(maps_) + " maps finished are kept in " + file_.string() +
         ": free space, then the same command resumes from them";
}

bool PartialLock::holdsFile(const fs::path& file) const noexcept {
  struct stat held {}, now {};
  if (fd_ < 0 || ::fstat(fd_, &held) != 0 || ::lstat(file.c_str(), &now) != 0) return false;
  return held.st_dev == now.st_dev && held.st_ino == now.st_ino;
}

bool PartialLock::removeHeldFile(const fs::path& file) const noexcept {
  return holdsFile(file) && ::unlink(file.c_str()) == 0;
}

fs::path PartialLock::heldFilePath() const {
  if (fd_ < 0) throw std::logic_error("PartialLock::heldFilePath: no file held");
  return fs::path("/proc/self/fd") / std::to_string(fd_);
}

void PartialLog::remove() {
  out_.close();
  removeOwnLog(file_, lock_);
}

void PartialLog::removeUnlessResumable() noexcept {
  if (maps_ != 0) return;  // finished maps are kept, whatever stopped the sweep
  try {
    removeOwnLog(file_, lock_);
  } catch (...) {  // out of memory: what was not removed stays for the user
  }
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
