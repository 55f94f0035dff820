// Helpers of runSweep (sweep_run.cpp, sweep_partial.cpp); not part of the public API.
#pragma once

#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <vector>
#include <mutex>
#include <string>
#include <utility>

#include "occsweep/io/locked_file.hpp"
#include "occsweep/sweeps/results.hpp"
#include "occsweep/sweeps/sweep.hpp"

namespace occsweep::sweep_detail {

/// Locks a sweep's existing partial output (io's LockedFile::existing), after refusing a symbolic link or a file
/// that is not regular at its name: a second sweep into the same --out stops with "another occsweep is writing FILE"
/// (docs/results-format.md, "Results store").
[[nodiscard]] LockedFile lockPartial(const std::filesystem::path& file);

/// Throws naming `file` when it is a symbolic link or not a regular file: what occsweep never writes through,
/// replaces or removes at a partial output's name, even with --force.
void requireOwnablePartial(const std::filesystem::path& file);

/// Finished maps of an interrupted run: OUT.partial.jsonl, a header line then one map per line. A line cut by a
/// kill is ignored (its map is simply done again). With `twin` (the observable-truth results of the same maps,
/// SweepConfig::observable_out), only lines carrying the twin's counts count, which go into `*twin`. The log is
/// locked into `lock`. Only a regular file with one name whose first line is a sweep's header is read: any other file
/// is refused, even with `force`, and so is a log with bytes written into it (a line other than a last one cut by a
/// kill that is not JSON); one of other work too unless `force` (then `lock` is held and nothing is returned: the log
/// is started anew).
[[nodiscard]] std::map<std::uint64_t, MapResult> loadPartial(const std::filesystem::path& partial,
                                                             const ResultsHeader& header, bool force,
                                                             std::map<std::uint64_t, std::string>& engine_of,
                                                             std::map<std::uint64_t, MapResult>* twin,
                                                             LockedFile& lock);

/// Removes occsweep's own partial log of the same work as `header` that a complete output superseded (a kill came
/// between the results' rename and the log's removal): never while another sweep holds it.
void removeSupersededLog(const std::filesystem::path& partial, const ResultsHeader& header);

/// A partial-log line's field holding the twin's thresholds and AUC.
inline constexpr const char* kTwinField = "observable";

/// "; the N maps finished are kept in FILE: ...", what an error message adds ("" when none is finished): a partial
/// output keeps every finished map through any error (docs/io.md, "Outputs and --force").
[[nodiscard]] std::string keptMapsNote(std::size_t maps, const std::filesystem::path& partial);

/// OUT.partial.jsonl while a sweep runs: a header line, then one line per finished map, each flushed. It is what a
/// killed or failed sweep resumes from, so an error keeps it when it holds a finished map; a failed write (a full
/// disk) cuts it back to its last whole map (docs/io.md, "Outputs and --force").
class PartialLog {
 public:
  /// Continues the log of `maps_done` finished maps, or (none) starts it anew with `header`'s line. Throws
  /// OutputError when it cannot be written.
  /// `lock` holds the existing log (loadPartial), which is replaced when no map of it is done.
  PartialLog(std::filesystem::path file, const ResultsHeader& header, std::size_t maps_done, LockedFile lock);
  ~PartialLog();
  PartialLog(const PartialLog&) = delete;
  PartialLog& operator=(const PartialLog&) = delete;

  /// Appends a finished map's line; safe from several threads. Throws OutputError when the write fails, saying
  /// how many maps the log keeps (keptNote).
  void append(const nlohmann::json& line);
  /// "; the N maps finished are kept in FILE: ...", what an error message adds ("" when none is finished).
  [[nodiscard]] std::string keptNote() const;
  /// The results are written: closes and removes the log.
  void remove();

 private:
  void removeUnlessResumable() noexcept;

  std::filesystem::path file_;
  LockedFile lock_;
  std::ofstream out_;
  std::mutex mutex_;
  std::size_t maps_;
  std::uintmax_t whole_bytes_ = 0;  ///< the log's size at the end of its last whole line
  bool failed_ = false;             ///< a write failed: the log was cut back, and takes no more lines
  std::string failure_;
};

/// True when `file` holds complete results of the same work as `header` (the twin of a finished sweep); false
/// when it is missing or other work. Throws for a file that is not occsweep's results (never replaced).
[[nodiscard]] bool completeResultsOf(const std::filesystem::path& file, const ResultsHeader& header);

/// Where one grid's finished maps go (sweep_outputs.cpp): a JSON file written whole at the end (OUT.partial.jsonl
/// while it runs), or a results store written batch by batch (OUT.partial, renamed to OUT when complete). Made
/// after the output checks: the same work's complete output is returned as it is, other work refused unless
/// --force, and only occsweep's own results replaced.
/// What every map of a sweep counts at each threshold: TP+FP+FN+TN (the evaluated region) and TP+FN (its truth).
struct RegionCounts {
  std::uint64_t region = 0, truth = 0;
};

/// Refuses (naming `partial`) resumed maps that count another region or truth than this sweep's maps.
void requireRegionOfThisSweep(const std::filesystem::path& partial, const RegionCounts& found,
                              const RegionCounts& counted);

class GridOutput {
 public:
  virtual ~GridOutput() = default;
  /// The same work's complete results already at the output (JSON: whole; a store: its header): nothing to count.
  [[nodiscard]] virtual const std::optional<ResultsFile>& complete() const = 0;
  /// The maps a killed run finished, in increasing index.
  [[nodiscard]] virtual std::vector<std::uint64_t> finished() const = 0;
  [[nodiscard]] virtual std::filesystem::path partial() const = 0;
  /// Opens the partial output for `todo` maps to count, each counting `counted`'s voxels: a resumed map that counts
  /// others is not this sweep's, and the sweep stops before counting (docs/io.md, "Ownership").
  virtual void begin(std::size_t todo, const RegionCounts& counted) = 0;
  /// A counted batch: its maps (and twins), and their positions among the maps to count. From several threads.
  virtual void add(std::vector<MapResult>&& maps, std::vector<MapResult>&& twin,
                   const std::vector<std::size_t>& positions) = 0;
  /// Writes the complete results atomically. Returns them (JSON: whole; a store: its header only).
  [[nodiscard]] virtual ResultsFile finish(double seconds) = 0;
};

/// A store for ".db"/".sqlite" (isStorePath), JSON otherwise. `h` and `c` must outlive it.
[[nodiscard]] std::unique_ptr<GridOutput> makeGridOutput(const SweepConfig& c, const ResultsHeader& h,
                                                         const std::string& engine);

}  // namespace occsweep::sweep_detail
