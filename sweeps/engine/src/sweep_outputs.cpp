// Where a grid's finished maps go (sweep_internal.hpp, GridOutput): a JSON file written whole at the end, with
// OUT.partial.jsonl while the sweep runs, or a results store written batch by batch into OUT.partial and renamed to
// OUT when complete (docs/results-format.md, "Results store"). Both resume what a killed run finished.
#include <algorithm>
#include <chrono>
#include <iostream>
#include <iterator>
#include <map>
#include <mutex>
#include <optional>
#include <set>

#include "occsweep/io/bounded_read.hpp"
#include "occsweep/io/ownership.hpp"
#include "occsweep/sweeps/results_file.hpp"
#include "occsweep/sweeps/results_store.hpp"
#include "occsweep/sweeps/results_verify.hpp"
#include "sweep_internal.hpp"

namespace occsweep::sweep_detail {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

using Clock = std::chrono::steady_clock;

bool hasTwin(const SweepConfig& c) { return !c.observable_out.empty(); }

// Maps finished before, read from the partial log of an interrupted run.
struct FinishedMaps {
  std::map<std::uint64_t, MapResult> done, twin_done;
  std::map<std::uint64_t, std::string> engine_of;  // provenance of every finished map
};

// Maps counted by this run, in the order of the work.
struct CountedMaps {
  std::vector<MapResult> maps, twin;
};

ResultsHeader twinHeader(ResultsHeader h) {
  h.truth = TruthMode::Observable;
  return h;
}

// What is at `out` already, read by `read` (JSON whole, a store's header): nothing, or occsweep's complete results of
// the same work. Anything else is refused unless --force (then replaced), and only occsweep's results are replaced
// even then (docs/io.md, "Outputs and --force").
std::optional<ResultsFile> completeSameWork(const SweepConfig& c, const ResultsHeader& h,
                                            ResultsFile (*read)(const fs::path&)) {
  requireCompanionName(c.out, partialOutputPath(c.out).string().substr(c.out.string().size()));
  checkOutputTarget(c.out, true, resultsOutput());  // also when absent: then nothing may replace what appears
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(c.out, ec))) return std::nullopt;
  ResultsFile old = read(c.out);
  std::string why;
  if (!sameWork(old.header, h, true, &why) && !c.force)
    throw std::runtime_error(c.out.string() + ": holds results of other work (" + why +
                             "); --force replaces it, or choose another --out");
  if (!why.empty() || !old.complete) return std::nullopt;
  // Taken as this sweep's results, and printed by reproduce, only when it passes every check of `results check`
  // (its grid's maps, each once): a file edited since would otherwise be reused as it is.
  try {
    (void)checkResultsFile(c.out, {});
  } catch (const std::exception& e) {
    if (!c.force)
      throw std::runtime_error(std::string(e.what()) + " (the results at --out fail `results check`); --force sweeps "
                               "them anew, or choose another --out");
    return std::nullopt;
  }
  return old;
}

// The twin at `observable_out`, when it is to be written: nothing, or occsweep's results of this same work (a kill
// came between the two renames), or with --force occsweep's results of other work. A user's file is refused even
// then (checkOutputTarget), like `--out` (completeSameWork).
void requireTwinReplaceable(const SweepConfig& c, const ResultsHeader& h) {
  checkOutputTarget(c.observable_out, true, resultsOutput());
  std::error_code ec;
  if (c.force || !fs::exists(fs::symlink_status(c.observable_out, ec))) return;
  std::string why = "it cannot be read";
  try {
    if (sameWork(readResultsHeader(c.observable_out).header, twinHeader(h), true, &why)) return;
  } catch (const std::exception& e) {
    why = e.what();
  }
  throw std::runtime_error(c.observable_out.string() + ": holds results of other work (" + why +
                           "); --force replaces it, or choose another --out");
}

// The same sweep's own complete JSON file (and twin) is returned as it is. The twin too replaces only occsweep's own
// results (a user's file there is refused before any work).
std::optional<ResultsFile> checkOutputs(const SweepConfig& c, const ResultsHeader& h) {
  std::optional<ResultsFile> old = completeSameWork(c, h, &readResults);
  if (old && (!hasTwin(c) || completeResultsOf(c.observable_out, twinHeader(h)))) {
    // Superseded (a kill came between the rename and the removal): removed only when it is occsweep's log.
    removeSupersededLog(partialOutputPath(c.out), h);
    return old;
  }
  if (hasTwin(c)) requireTwinReplaceable(c, h);
  return std::nullopt;
}

// Every engine that made a map of the file.
void recordEngines(ResultsHeader& h, const FinishedMaps& finished, const std::string& engine) {
  std::set<std::string> engines;
  for (const auto& [index, name] : finished.engine_of)
    if (finished.done.count(index)) engines.insert(name);
  if (engines.empty()) engines.insert(engine);
  setEngines(h, engines);
}

// The results file (and twin), complete: the maps finished before and now.
ResultsFile finishSweep(ResultsHeader h, FinishedMaps& finished, CountedMaps counted, const std::string& engine) {
  for (auto& r : counted.maps) finished.engine_of[r.map_index] = engine, finished.done[r.map_index] = std::move(r);
  for (auto& r : counted.twin) finished.twin_done[r.map_index] = std::move(r);
  recordEngines(h, finished, engine);
  ResultsFile f;
  f.header = std::move(h);
  for (auto& [_, r] : finished.done) f.maps.push_back(std::move(r));
  f.complete = true;
  return f;
}

// Writes the files atomically, the twin first: a complete main file promises a complete twin. A failed write (a full
// disk) keeps the partial log, and says so.
void writeSweepResults(const ResultsFile& f, FinishedMaps& finished, const SweepConfig& c,
                       PartialLog& log) {
  try {
    if (hasTwin(c)) {
      ResultsFile o;
      o.header = twinHeader(f.header);
      for (auto& [_, r] : finished.twin_done) o.maps.push_back(std::move(r));
      o.complete = true;
      o.seconds = f.seconds;
      writeResults(o, c.observable_out);
    }
    writeResults(f, c.out);
  } catch (const OutputConflict&) {
    throw;  // a file put at --out meanwhile: every map stays in the log, for a run once it is moved away
  } catch (const OutputError& e) {
    throw OutputError(e.what() + log.keptNote());
  }
  log.remove();
}

// What both outputs keep: the sweep, its header, its engine, the partial file and the complete results found.
class OutputBase : public GridOutput {
 public:
  OutputBase(const SweepConfig& c, const ResultsHeader& h, std::string engine)
      : c_(c), h_(h), engine_(std::move(engine)), partial_(partialOutputPath(c.out)) {
    reportLeftoverTemporaries(partial_);  // a resumed partial output makes no temporary that would name them
  }
  const std::optional<ResultsFile>& complete() const override { return existing_; }
  fs::path partial() const override { return partial_; }

 protected:
  const SweepConfig& c_;
  const ResultsHeader& h_;
  std::string engine_;
  fs::path partial_;
  std::optional<ResultsFile> existing_;
};

// JSON: finished maps logged to OUT.partial.jsonl as they come, the file (and twin) written whole at the end.
class JsonOutput final : public OutputBase {
 public:
  JsonOutput(const SweepConfig& c, const ResultsHeader& h, std::string engine)
      : OutputBase(c, h, std::move(engine)) {
    existing_ = checkOutputs(c, h);
    if (existing_) return;
    finished_.done =
        loadPartial(partial_, h, c.force, finished_.engine_of, hasTwin(c) ? &finished_.twin_done : nullptr, lock_);
  }
  std::vector<std::uint64_t> finished() const override {
    std::vector<std::uint64_t> done;
    for (const auto& [index, _] : finished_.done) done.push_back(index);
    return done;
  }
  void begin(std::size_t todo, const RegionCounts& counted) override {
    if (!finished_.done.empty()) {  // the resumed maps all count one region (loadPartial): one speaks for all
      const ConfusionCounts& n = finished_.done.begin()->second.thresholds.front().counts;
      requireRegionOfThisSweep(partial_, {n.tp + n.fp + n.fn + n.tn, n.tp + n.fn}, counted);
    }
    if (c_.out.has_parent_path()) fs::create_directories(c_.out.parent_path());
    log_.emplace(partial_, h_, finished_.done.size(), std::move(lock_));
    counted_.maps.resize(todo);
    counted_.twin.resize(hasTwin(c_) ? todo : 0);
  }
  // Each finished map logged at once (with its engine, for provenance across resumes: docs/results-format.md).
  void add(std::vector<MapResult>&& maps, std::vector<MapResult>&& twin, const std::vector<std::size_t>& positions) override {
    for (std::size_t j = 0; j < positions.size(); ++j) {
      json line = toJson(maps[j], h_.parameters);
      line["engine"] = engine_;
      if (hasTwin(c_)) {
        const json oj = toJson(twin[j], h_.parameters);
        line[kTwinField] = {{"thresholds", oj.at("thresholds")}, {"auc", oj.at("auc")}};
        counted_.twin[positions[j]] = std::move(twin[j]);
      }
      log_->append(line);
      counted_.maps[positions[j]] = std::move(maps[j]);
    }
  }
  ResultsFile finish(double seconds) override {
    ResultsFile f = finishSweep(h_, finished_, std::move(counted_), engine_);
    f.seconds = seconds;
    writeSweepResults(f, finished_, c_, *log_);
    return f;
  }

 private:
  FinishedMaps finished_;
  CountedMaps counted_;
  LockedFile lock_;  // the log found, until the PartialLog takes it
  std::optional<PartialLog> log_;
};

// The same sweep's complete store at `out` is left as it is (its header returned).
std::optional<ResultsFile> completeStore(const SweepConfig& c, const ResultsHeader& h) {
  std::optional<ResultsFile> old = completeSameWork(c, h, &readResultsHeader);
  const fs::path partial = partialOutputPath(c.out);
  // Superseded (a kill came between the rename and the removal): removed only when occsweep's and not being written.
  if (old && isOccsweepStore(partial)) {
    try {
      const LockedFile lock = lockPartial(partial);
      lock.removeHeldFile(partial);
    } catch (const std::exception&) {
    }
  }
  return old;
}

// OUT.partial of the same work, resumed (locked in `lock`); of other work, refused unless --force (then `replace`:
// started anew when the counting begins). Only a store carrying occsweep's application_id is resumed or replaced:
// anything else there (a user's file, a symbolic link, another program's database) is refused, even with --force
// (docs/results-format.md, "Results store"). It is opened for writing: SQLite rolls back the batch a kill left open.
std::optional<ResultsStore> resumableStore(const fs::path& partial, const ResultsHeader& h, bool force,
                                           LockedFile& lock, bool& replace) {
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(partial, ec))) return std::nullopt;
  requireOwnablePartial(partial);
  if (!isOccsweepStore(partial))
    throw std::runtime_error(partial.string() + ": not a partial results store of occsweep's (no occsweep "
                             "application_id); occsweep never replaces or removes it (even with --force): remove it, "
                             "or choose another --out");
  requireOnlyRollbackJournalBeside(partial);  // SQLite would roll a user's file there into the store and delete it
  lock = lockPartial(partial);
  std::optional<ResultsStore> old;
  std::string why;
  try {
    old.emplace(ResultsStore::open(partial, true));
    if (sameWork(old->header(), h, true, &why)) return old;
  } catch (const std::exception& e) {
    if (!force) throw std::runtime_error(std::string(e.what()) + "; --force starts it anew, or choose another --out");
  }
  if (!force)
    throw std::runtime_error(partial.string() + ": an interrupted sweep of other work (" + why +
                             "); --force replaces it, or choose another --out");
  replace = true;
  return std::nullopt;
}

// Finished maps into the store from the counting threads: one transaction a second at most (or per 4,096 maps),
// since each commit waits for the disk. A kill loses at most that second of work (docs/results-format.md). A failed
// write (a full disk) rolls back its batch and stops every later one: the maps committed before it stay in the
// partial store, and the error says how many (docs/io.md, "Outputs and --force").
class StoreWriter {
 public:
  StoreWriter(ResultsStore& store, std::string engine, fs::path partial)
      : store_(store), engine_(std::move(engine)), partial_(std::move(partial)) {}
  void add(std::vector<MapResult>&& maps) {
    const std::lock_guard lock(mutex_);
    std::move(maps.begin(), maps.end(), std::back_inserter(pending_));
    if (pending_.size() >= kMaxPending || Clock::now() - last_commit_ >= std::chrono::seconds(1)) commit();
  }
  void flush() {
    const std::lock_guard lock(mutex_);
    commit();
  }

 private:
  static constexpr std::size_t kMaxPending = 4096;
  // Called under mutex_: no other thread uses the store's connection meanwhile.
  void commit() {
    if (!failure_.empty()) throw OutputError(failure_);
    try {
      if (!pending_.empty()) store_.append(pending_, engine_);
    } catch (const OutputError&) {
      appendOneByOne();  // as many of the batch's maps as the disk still takes are kept
    }
    pending_.clear();
    last_commit_ = Clock::now();
  }
  // The pending maps one transaction each, after their batch failed (a full disk): stops at the first that fails,
  // with the error and the count of maps the store keeps.
  void appendOneByOne() {
    try {
      for (const MapResult& m : pending_) store_.append({m}, engine_);
    } catch (const OutputError& e) {
      failure_ = e.what() + keptMapsNote(store_.mapCount(), partial_);
      throw OutputError(failure_);
    }
  }
  ResultsStore& store_;
  std::string engine_;
  fs::path partial_;
  std::mutex mutex_;
  std::vector<MapResult> pending_;
  std::string failure_;
  Clock::time_point last_commit_ = Clock::now();
};

// A store: OUT.partial resumed when there is one of the same work, else created when the counting begins; renamed to
// OUT when complete. Destroyed by an error before any map was stored, it removes the partial store it created.
class StoreOutput final : public OutputBase {
 public:
  StoreOutput(const SweepConfig& c, const ResultsHeader& h, std::string engine)
      : OutputBase(c, h, std::move(engine)) {
    if (hasTwin(c)) throw std::invalid_argument("sweep: observable_out is written as JSON only (a results store has no twin)");
    existing_ = completeStore(c, h);
    if (existing_) return;
    store_ = resumableStore(partial_, h, c.force, lock_, replace_);
    if (store_) requireHeldPartial();
  }
  ~StoreOutput() override {
    if (!store_ || renamed_) return;
    try {
      if (store_->mapCount() != 0) return;  // what the next run resumes from
    } catch (const std::exception&) {
    }
    store_.reset();
    lock_.removeHeldFile(partial_);  // only the store this sweep made, never a file put at its name meanwhile
  }
  StoreOutput(const StoreOutput&) = delete;
  StoreOutput& operator=(const StoreOutput&) = delete;

  std::vector<std::uint64_t> finished() const override { return store_ ? store_->mapIndices() : std::vector<std::uint64_t>{}; }
  void begin(std::size_t, const RegionCounts& counted) override {
    // A store keeps its maps' region (every append checks it); its truth speaks for it here.
    if (store_ && store_->mapCount() != 0)
      requireRegionOfThisSweep(partial_, {counted.region, store_->truthVoxels()}, counted);
    if (c_.out.has_parent_path()) fs::create_directories(c_.out.parent_path());
    if (!store_) {
      requireNoJournalBeside(partial_);  // a new store: any journal there is not its own
      requireNoJournalBeside(c_.out);
      // Created beside it, locked, then put in place: a second sweep into the same --out finds it locked.
      // Made at a temporary, so its journal is kept in memory: a kill during the creation leaves no `-journal`.
      lock_ = LockedFile::publish(partial_, replace_ ? &lock_ : nullptr, [&](const fs::path& t) {
        (void)ResultsStore::create(t, h_, StoreUse::Temporary);
      });
      // Opened by name (SQLite names its journal after it): the file this sweep made, or the sweep stops.
      try {
        store_.emplace(ResultsStore::open(partial_, true));
      } catch (const std::exception&) {
        requireHeldPartial();  // a user's file put at its name meanwhile: said so, rather than "not a database"
        throw;
      }
      requireHeldPartial();
    }
    writer_.emplace(*store_, engine_, partial_);
  }
  void add(std::vector<MapResult>&& maps, std::vector<MapResult>&&, const std::vector<std::size_t>&) override {
    writer_->add(std::move(maps));
  }
  ResultsFile finish(double seconds) override {
    ResultsFile f;
    f.header = h_;
    writer_->flush();
    const std::vector<std::string> engines = store_->engineNames();
    setEngines(f.header, {engines.begin(), engines.end()});
    try {
      store_->finish(f.header, seconds);
    } catch (const OutputError& e) {  // every map is committed: only the closing record failed
      throw OutputError(e.what() + keptMapsNote(store_->mapCount(), partial_));
    }
    store_.reset();  // closed before the rename
    requireHeldPartial();
    renameIntoPlace(partial_, c_.out);  // never over a file created at --out meanwhile (docs/robustness.md)
    renamed_ = true;
    f.complete = true;
    f.seconds = seconds;
    return f;
  }

 private:
  // SQLite refuses to write a store moved away meanwhile; the name is checked again before the rename.
  void requireHeldPartial() const {
    if (!lock_.holdsFile(partial_))
      throw std::runtime_error(partial_.string() + ": was moved or replaced while occsweep was writing it; what "
                               "stands at its name now is left as it is");
  }
  LockedFile lock_;  // before store_: released after the store is closed
  std::optional<ResultsStore> store_;
  std::optional<StoreWriter> writer_;
  bool replace_ = false, renamed_ = false;
};

}  // namespace

std::unique_ptr<GridOutput> makeGridOutput(const SweepConfig& c, const ResultsHeader& h, const std::string& engine) {
  if (isStorePath(c.out)) return std::make_unique<StoreOutput>(c, h, engine);
  return std::make_unique<JsonOutput>(c, h, engine);
}

}  // namespace occsweep::sweep_detail

namespace occsweep {
std::filesystem::path partialOutputPath(const std::filesystem::path& out) {
  return out.string() + (isStorePath(out) ? ".partial" : ".partial.jsonl");
}
}  // namespace occsweep
