// The partial log of a sweep: what a killed sweep resumes from, held by io's LockedFile (docs/io.md, "Ownership").
#include <cerrno>
#include <cstring>
#include <fstream>
#include <sys/stat.h>
#include <unistd.h>

#include <optional>

#include "occsweep/io/bounded_read.hpp"
#include "occsweep/io/temporaries.hpp"
#include "occsweep/sweeps/results_verify.hpp"
#include "sweep_internal.hpp"

namespace occsweep::sweep_detail {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {




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
// LockedFile::existing). A file at that reserved name whose first line is not a sweep's header is a user's: never
// resumed from, replaced or removed (docs/io.md, "Ownership").
ResultsHeader ownLogHeader(const fs::path& partial, const LockedFile& lock) {
  std::optional<ResultsHeader> header = logHeader(lock.heldFilePath());
  if (!header)
    throw std::runtime_error(partial.string() + ": not a partial log of occsweep's (its first line is not a sweep's "
                             "header); occsweep never resumes from, replaces or removes it (even with --force): remove "
                             "it, or choose another --out");
  return std::move(*header);
}

}  // namespace

LockedFile lockPartial(const fs::path& file) {
  requireOwnablePartial(file);
  return LockedFile::existing(file);
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
void dropCutLine(const fs::path& partial, const LockedFile& lock, std::uintmax_t whole) {
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
LogEnd readLogLines(const fs::path& partial, const LockedFile& lock,
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

void requireRegionOfThisSweep(const fs::path& partial, const RegionCounts& found, const RegionCounts& counted) {
  if (found.region == counted.region && found.truth == counted.truth) return;
  throw std::runtime_error(partial.string() + ": its maps count " + std::to_string(found.region) + " voxels (" +
                           std::to_string(found.truth) + " of truth), this sweep's count " +
                           std::to_string(counted.region) + " (" + std::to_string(counted.truth) + "): not the maps " +
                           "occsweep wrote for this sweep; occsweep never resumes from, replaces or removes it (even " +
                           "with --force): remove it, or choose another --out");
}

void removeSupersededLog(const fs::path& partial, const ResultsHeader& header) {
  std::error_code ec;
  if (!fs::is_regular_file(fs::symlink_status(partial, ec))) return;
  try {
    const LockedFile lock = lockPartial(partial);  // never while another sweep writes it
    if (!sameWork(ownLogHeader(partial, lock), header, true, nullptr)) return;
    (void)readLogLines(partial, lock, {});  // only what occsweep wrote
    lock.removeHeldFile(partial);
  } catch (const std::exception&) {  // another sweep writes it, it is not occsweep's, or it cannot be read: left
  }
}

std::map<std::uint64_t, MapResult> loadPartial(const fs::path& partial, const ResultsHeader& header, bool force,
                                               std::map<std::uint64_t, std::string>& engine_of,
                                               std::map<std::uint64_t, MapResult>* twin, LockedFile& lock) {
  std::map<std::uint64_t, MapResult> done;
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(partial, ec))) return done;
  lock = lockPartial(partial);
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

PartialLog::PartialLog(fs::path file, const ResultsHeader& header, std::size_t maps_done, LockedFile lock)
    : file_(std::move(file)), lock_(std::move(lock)), maps_(maps_done) {
  if (maps_done == 0) {
    // The header is written before the log appears under its name: a log without it is never occsweep's.
    lock_ = LockedFile::publish(file_, lock_.held() ? &lock_ : nullptr, [&](const fs::path& temporary) {
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

std::string keptMapsNote(std::size_t maps, const fs::path& partial) {
  if (maps == 0) return "";
  return "; the " + std::to_string(maps) + " maps finished are kept in " + partial.string() +
         ": free space, then the same command resumes from them";
}

std::string PartialLog::keptNote() const { return keptMapsNote(maps_, file_); }




void PartialLog::remove() {
  out_.close();
  lock_.removeHeldFile(file_);
}

void PartialLog::removeUnlessResumable() noexcept {
  if (maps_ != 0) return;  // finished maps are kept, whatever stopped the sweep
  try {
    lock_.removeHeldFile(file_);
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
