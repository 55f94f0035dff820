// The results store (docs/results-format.md, "Results store"): a sweep's results in one SQLite file, written as
// they are produced (one transaction per batch of maps) and read map by map, so that neither the sweep nor the
// commands reading it hold the whole grid in memory. JSON stays the format of small results and of export.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "occsweep/sweeps/results.hpp"
#include "occsweep/sweeps/results_file.hpp"
#include "occsweep/io/temporaries.hpp"

namespace occsweep {

/// True when `file` begins with SQLite's 16-byte header: a store, whatever its name.
[[nodiscard]] bool isResultsStore(const std::filesystem::path& file);
/// SQLite's application_id of every store occsweep creates ("OCSW"): what marks a file at a partial store's name
/// as occsweep's, to resume, replace or remove (docs/results-format.md, "Results store").
inline constexpr std::uint32_t kStoreApplicationId = 0x4F435357;
/// True when `file` is a regular file (not a symbolic link) with SQLite's header and occsweep's application_id.
[[nodiscard]] bool isOccsweepStore(const std::filesystem::path& file);

/// How a new store is written: Durable keeps a rollback journal beside it (a partial store a kill must leave
/// consistent); Temporary keeps it in memory (a temporary renamed into place when complete, removed on a kill).
enum class StoreUse { Durable, Temporary };

/// Refuses (OutputError, exit 2) to make a new store at `store` while an entry stands at SQLite's names beside it
/// (STORE-journal, -wal, -shm): SQLite would take it for the new store's unfinished transaction, roll it into the
/// store and delete it, a user's file as much as a stale journal (docs/io.md, "Ownership").
void requireNoJournalBeside(const std::filesystem::path& store);
/// Before an existing store is opened to be written (a partial store resumed): as requireNoJournalBeside, except a
/// regular file at STORE-journal that begins with SQLite's rollback-journal header, what a kill of occsweep's writing
/// leaves and SQLite rolls back on opening. Anything else there (a user's file, an empty file, a link, a -wal or
/// -shm) would be rolled into the store and deleted: refused (OutputError, exit 2), naming it.
void requireOnlyRollbackJournalBeside(const std::filesystem::path& store);

/// One store, open. Errors are std::runtime_error naming the file (and the table and field where one is wrong).
class ResultsStore {
 public:
  /// A new store at `file` holding `header`; incomplete until finish(). Durable: `file` must not exist. Temporary:
  /// `file` is the empty file its claim made (OutputFile, RegisteredTemporary), opened and never created.
  [[nodiscard]] static ResultsStore create(const std::filesystem::path& file, const ResultsHeader& header,
                                           StoreUse use = StoreUse::Durable);
  /// An existing store, checked to be an occsweep results store of a version this program reads.
  [[nodiscard]] static ResultsStore open(const std::filesystem::path& file, bool writable = false);

  ResultsStore(ResultsStore&&) noexcept;
  ResultsStore& operator=(ResultsStore&&) noexcept;
  ~ResultsStore();

  /// PRAGMA quick_check: every page readable and consistent (a truncated or bit-flipped file throws).
  void verifyIntegrity() const;
  [[nodiscard]] const ResultsHeader& header() const;
  [[nodiscard]] bool complete() const;
  [[nodiscard]] double seconds() const;
  [[nodiscard]] std::uint64_t mapCount() const;
  /// TP+FN of every threshold of every map (the truth's voxels); 0 before the first map.
  [[nodiscard]] std::uint64_t truthVoxels() const;

  /// Appends finished maps in one transaction: a kill loses at most this batch. Each map must count the region
  /// and truth of the first map stored (TP+FP+FN+TN and TP+FN), which the store keeps once; a map that does not
  /// throws (a sweep's bug, never stored). `engine` is each map's provenance.
  void append(const std::vector<MapResult>& maps, const std::string& engine);
  /// The finished maps' indices, increasing, and every engine that made one (resuming a sweep).
  [[nodiscard]] std::vector<std::uint64_t> mapIndices() const;
  [[nodiscard]] std::vector<std::string> engineNames() const;
  /// Marks the store complete, with the final header (its engines) and the run's seconds.
  void finish(const ResultsHeader& header, double seconds);
  /// Every map in increasing map index. Full: each map's AUC is derived from its counts again and must match the
  /// stored one (a hand edit is caught, as in JSON); Summary: the stored AUC.
  void forEachMap(MapDetail detail, const MapVisitor& visit) const;

 private:
  struct Connection;
  explicit ResultsStore(std::unique_ptr<Connection> c);
  std::unique_ptr<Connection> c_;
};

/// `f` as a new store at `file`, atomically (a temporary beside it, renamed when complete).
void writeResultsStore(const ResultsFile& f, const std::filesystem::path& file);


}  // namespace occsweep
