// The partial log of a sweep: what a killed sweep resumes from.
#include <cerrno>
#include <fstream>

#include "occsweep/eval/bounded_read.hpp"
#include "sweep_internal.hpp"

namespace occsweep::sweep_detail {
namespace fs = std::filesystem;
using nlohmann::json;

std::map<std::uint64_t, MapResult> loadPartial(const fs::path& partial, const ResultsHeader& header, bool force,
                                               std::map<std::uint64_t, std::string>& engine_of,
                                               std::map<std::uint64_t, MapResult>* twin) {
  std::map<std::uint64_t, MapResult> done;
  if (fs::exists(fs::symlink_status(partial))) requireRegularFile(partial);  // a FIFO would block the sweep
  std::ifstream in(partial);
  std::string line;
  if (!std::getline(in, line)) return done;
  ResultsHeader old;
  try {
    old = parseHeader(json::parse(line), partial.string());
  } catch (const std::exception&) {
    return done;  // header cut short: nothing finished yet
  }
  std::string why;
  if (!sameWork(old, header, true, &why)) {
    if (force) return done;  // replaced: the log is truncated below
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

PartialLog::PartialLog(fs::path file, const ResultsHeader& header, std::size_t maps_done)
    : file_(std::move(file)), out_(file_, std::ios::app), maps_(maps_done) {
  if (maps_done == 0) {
    out_.close();
    out_.open(file_, std::ios::trunc);
    out_ << toJson(header).dump() << '\n' << std::flush;
  }
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

void PartialLog::remove() {
  out_.close();
  fs::remove(file_);
}

OutputError PartialLog::writeFailed() {
  write_failed_ = true;
  return OutputError(writeFailure(file_, errno));
}

void PartialLog::removeUnlessResumable() noexcept {
  std::error_code ec;
  if (maps_ == 0 || write_failed_) fs::remove(file_, ec);
}

bool completeResultsOf(const fs::path& file, const ResultsHeader& header) {
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(file, ec))) return false;
  checkOutputTarget(file, true, resultsOutput());
  try {
    const ResultsFile f = readResults(file);
    return f.complete && sameWork(f.header, header, true, nullptr);
  } catch (const std::exception&) {
    return false;  // occsweep's own but unreadable: replaced
  }
}

}  // namespace occsweep::sweep_detail
