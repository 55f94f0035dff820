// Helpers of runSweep (sweep_run.cpp, sweep_partial.cpp); not part of the public API.
#pragma once

#include <atomic>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <string>

#include "occsweep/sweeps/results.hpp"

namespace occsweep::sweep_detail {

/// Finished maps of an interrupted run: OUT.partial.jsonl, a header line then one map per line. A line cut by a
/// kill is ignored (its map is simply done again). With `twin` (the observable-truth results of the same maps,
/// SweepConfig::observable_out), only lines carrying the twin's counts count, which go into `*twin`.
[[nodiscard]] std::map<std::uint64_t, MapResult> loadPartial(const std::filesystem::path& partial,
                                                             const ResultsHeader& header, bool force,
                                                             std::map<std::uint64_t, std::string>& engine_of,
                                                             std::map<std::uint64_t, MapResult>* twin);

/// A partial-log line's field holding the twin's thresholds and AUC.
inline constexpr const char* kTwinField = "observable";

/// OUT.partial.jsonl while a sweep runs: a header line, then one line per finished map, each flushed. It is what a
/// killed sweep resumes from, so an error keeps it, unless it holds no finished map or a write failed (a full
/// disk): then it is removed rather than leave the disk full (docs/robustness.md).
class PartialLog {
 public:
  /// Continues the log of `maps_done` finished maps, or (none) starts it anew with `header`'s line. Throws
  /// OutputError when it cannot be written.
  PartialLog(std::filesystem::path file, const ResultsHeader& header, std::size_t maps_done);
  ~PartialLog();
  PartialLog(const PartialLog&) = delete;
  PartialLog& operator=(const PartialLog&) = delete;

  /// Appends a finished map's line; safe from several threads. Throws OutputError when the write fails.
  void append(const nlohmann::json& line);
  /// Writing the results failed (a full disk): the log is removed with the error.
  void dropOnError() { write_failed_ = true; }
  /// The results are written: closes and removes the log.
  void remove();

 private:
  [[nodiscard]] OutputError writeFailed();
  void removeUnlessResumable() noexcept;

  std::filesystem::path file_;
  std::ofstream out_;
  std::mutex mutex_;
  std::size_t maps_;
  std::atomic<bool> write_failed_{false};
};

/// True when `file` holds complete results of the same work as `header` (the twin of a finished sweep); false
/// when it is missing or other work. Throws for a file that is not occsweep's results (never replaced).
[[nodiscard]] bool completeResultsOf(const std::filesystem::path& file, const ResultsHeader& header);

}  // namespace occsweep::sweep_detail
