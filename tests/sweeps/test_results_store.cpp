// The results store (docs/results-format.md, "Results store"): the same numbers as JSON, byte-identical export,
// a kill loses at most the open transaction and resumes, a hand edit is caught, and a user's database is never
// replaced.
#include <catch2/catch.hpp>

#include <csignal>
#include <fstream>
#include <sstream>
#include <thread>

#include <sqlite3.h>
#include <sys/wait.h>
#include <unistd.h>

#include "occsweep/sweeps/merge.hpp"
#include "occsweep/sweeps/results_store.hpp"
#include "occsweep/sweeps/results_verify.hpp"
#include "occsweep/sweeps/sweep.hpp"
#include "small_scene.hpp"
#include "test_helpers.hpp"

using namespace occsweep;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {

const fs::path kGolden = fs::path(OCCSWEEP_SOURCE_DIR) / "results" / "builtin";

using test::smallScene;
using test::quietSweep;

std::string exportedJson(const fs::path& file) {
  std::ostringstream out;
  exportJson(file, out);
  return out.str();
}

// Runs one SQL statement on a store, as a user editing it by hand would.
void editStore(const fs::path& file, const std::string& sql) {
  sqlite3* db = nullptr;
  REQUIRE(sqlite3_open(file.c_str(), &db) == SQLITE_OK);
  char* error = nullptr;
  const int rc = sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &error);
  INFO((error ? error : ""));
  sqlite3_free(error);
  sqlite3_close(db);
  REQUIRE(rc == SQLITE_OK);
}

std::string checkError(const fs::path& file) {
  try {
    (void)checkResultsFile(file, "");
  } catch (const std::exception& e) {
    return e.what();
  }
  return "passed";
}

std::uint64_t storedMaps(const fs::path& partial) {
  try {
    return ResultsStore::open(partial).mapCount();
  } catch (const std::exception&) {
    return 0;  // not created yet, or its first transaction still open
  }
}

// `occsweep sweep --grid reduction --threads 1` into `out`, in a child process: 18,000 maps, several commits.
pid_t startReductionSweep(const fs::path& data, const fs::path& out) {
  const pid_t child = ::fork();
  if (child == 0) {
    ::execl(OCCSWEEP_CLI, OCCSWEEP_CLI, "sweep", "--dataset", data.c_str(), "--grid", "reduction", "--out", out.c_str(),
            "--threads", "1", "--quiet", static_cast<char*>(nullptr));
    std::_Exit(127);
  }
  return child;
}

void waitForFirstCommit(const fs::path& partial) {
  for (int i = 0; i < 6000 && storedMaps(partial) == 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(2));
}

}  // namespace

TEST_CASE("a sweep into a store has the JSON sweep's numbers, and its export is the JSON file byte for byte") {
  const auto dir = test::scratch("store-sweep");
  const auto data = smallScene(dir);
  for (const std::string grid : {"knn-opt", "octomap-opt", "sor-octomap-opt"}) {
    const ResultsFile json = runSweep(quietSweep(data, grid, dir / (grid + ".json")));
    const SweepSummary summary = sweepToFile(quietSweep(data, grid, dir / (grid + ".db")));
    CHECK(isResultsStore(dir / (grid + ".db")));
    CHECK(summary.maps == json.maps.size());
    const ResultsFile stored = readResults(dir / (grid + ".db"));
    CHECK(stored.complete);
    CHECK(resultDifferences(json, stored).empty());
    CHECK(checkResultsFile(dir / (grid + ".db"), data).grid_checked);
    // Timings aside (two runs), the export is the JSON sweep's file: written once more from `json` with the
    // stored seconds, it must be the exported bytes exactly.
    ResultsFile same = json;
    same.seconds = stored.seconds;
    for (std::size_t i = 0; i < same.maps.size(); ++i) same.maps[i].seconds = stored.maps[i].seconds;
    writeResults(same, dir / (grid + ".again.json"));
    CHECK(exportedJson(dir / (grid + ".db")) == test::bytesOf(dir / (grid + ".again.json")));
  }
}

TEST_CASE("the golden files round-trip through a store to what writeResults writes of them, byte for byte") {
  const auto dir = test::scratch("store-golden");
  for (const std::string grid : {"knn-opt", "octomap-opt"}) {
    const fs::path golden = kGolden / (grid + ".json");
    writeResultsStore(readResults(golden), dir / (grid + ".db"));
    // (The golden files predate map.engines, which writeResults adds: the same bytes otherwise.)
    writeResults(readResults(golden), dir / (grid + ".json"));
    CHECK(exportedJson(dir / (grid + ".db")) == test::bytesOf(dir / (grid + ".json")));
    // The CSV has one row per combination, with FN and TN derived from the stored region.
    std::ostringstream csv;
    exportCsv(dir / (grid + ".db"), csv);
    const ResultsFile g = readResults(golden);
    std::size_t combinations = 0;
    for (const auto& m : g.maps) combinations += m.thresholds.size();
    std::istringstream rows(csv.str());
    std::string header, row, last;
    std::getline(rows, header);
    std::size_t n = 0;
    while (std::getline(rows, row)) ++n, last = row;
    CHECK(n == combinations);
    const ThresholdResult& t = g.maps.back().thresholds.back();
    // (Fields joined by append: g++ 12 warns falsely on long operator+ chains of strings.)
    std::string key, counts;
    for (std::uint64_t v : {t.id, g.maps.back().map_index}) key.append(std::to_string(v)).append(",");
    for (std::uint64_t v : {t.counts.tp, t.counts.fp, t.counts.fn, t.counts.tn}) counts.append(",").append(std::to_string(v));
    CHECK(last.starts_with(key));
    CHECK_THAT(last, Contains(counts + ","));
  }
}

TEST_CASE("a sweep into a store killed part-way resumes from its partial store to the uninterrupted result") {
  const auto dir = test::scratch("store-resume");
  const auto data = smallScene(dir);
  // The reduction grid: 18,000 maps, several transactions of 4,096 (one map each a sweep of a few hundred is done
  // before its first commit).
  (void)sweepToFile(quietSweep(data, "reduction", dir / "reference.db"));
  const fs::path out = dir / "killed.db", partial = dir / "killed.db.partial";
  const pid_t child = startReductionSweep(data, out);
  // Wait until a transaction of maps is committed, then kill it hard (mid-transaction, most likely).
  waitForFirstCommit(partial);
  ::kill(child, SIGKILL);
  int status = 0;
  ::waitpid(child, &status, 0);
  REQUIRE(WIFSIGNALED(status));
  CHECK_FALSE(fs::exists(out));  // no half results
  const std::uint64_t finished = storedMaps(partial);
  CHECK(finished > 0);
  CHECK(finished < 18000);
  const auto r = test::runCli("sweep --dataset " + data.string() + " --grid reduction --out " + out.string());
  REQUIRE(r.exit_code == 0);
  CHECK_THAT(r.output, Contains("resuming ") && Contains(": " + std::to_string(finished) + " of 18000 maps done before"));
  CHECK_FALSE(fs::exists(partial));
  CHECK(resultDifferences(readResults(dir / "reference.db"), readResults(out)).empty());
  CHECK(checkResultsFile(out, "").maps == 18000);
}

TEST_CASE("a sweep into a store waits for a program reading it, and its numbers do not change") {
  // A user looks at a running sweep's partial store with Python's sqlite3; a read transaction holds a shared lock
  // that blocks the sweep's next commit. The sweep waits for it (it used to stop with "database is locked").
  const auto dir = test::scratch("store-read-while-written");
  const auto data = smallScene(dir);
  (void)sweepToFile(quietSweep(data, "reduction", dir / "reference.db"));
  const fs::path out = dir / "read.db", partial = dir / "read.db.partial";
  const pid_t child = startReductionSweep(data, out);
  waitForFirstCommit(partial);
  sqlite3* reader = nullptr;
  REQUIRE(sqlite3_open_v2(partial.c_str(), &reader, SQLITE_OPEN_READONLY, nullptr) == SQLITE_OK);
  // The shared lock is held from the first step of a read transaction until it ends.
  REQUIRE(sqlite3_exec(reader, "BEGIN; SELECT count(*) FROM maps;", nullptr, nullptr, nullptr) == SQLITE_OK);
  std::this_thread::sleep_for(std::chrono::milliseconds(2500));  // past the sweep's next commit (one a second)
  int status = 0;
  const pid_t ended = ::waitpid(child, &status, WNOHANG);
  CHECK(ended == 0);  // still running: waiting for the lock, or mapping
  REQUIRE(sqlite3_exec(reader, "COMMIT", nullptr, nullptr, nullptr) == SQLITE_OK);
  sqlite3_close(reader);
  if (ended == 0) ::waitpid(child, &status, 0);
  REQUIRE(WIFEXITED(status));
  REQUIRE(WEXITSTATUS(status) == 0);
  CHECK(resultDifferences(readResults(dir / "reference.db"), readResults(out)).empty());
}

TEST_CASE("a store edited by hand fails results check with the row named") {
  const auto dir = test::scratch("store-edited");
  const auto data = smallScene(dir);
  (void)sweepToFile(quietSweep(data, "octomap-opt", dir / "r.db"));
  REQUIRE(checkError(dir / "r.db") == "passed");
  SECTION("a count") {
    editStore(dir / "r.db", "UPDATE thresholds SET tp = tp + 1 WHERE id = 7");
    CHECK_THAT(checkError(dir / "r.db"), Contains("r.db") && Contains("auc does not match"));
  }
  SECTION("an AUC") {
    editStore(dir / "r.db", "UPDATE maps SET auc_anchored = 0.99 WHERE map_index = 3");
    CHECK_THAT(checkError(dir / "r.db"), Contains("maps row 3") && Contains("auc does not match"));
  }
  SECTION("a map removed") {
    editStore(dir / "r.db", "DELETE FROM maps WHERE map_index = 5");
    CHECK_THAT(checkError(dir / "r.db"), Contains("belongs to no map"));
  }
  SECTION("a map and its thresholds removed") {
    editStore(dir / "r.db", "DELETE FROM thresholds WHERE id BETWEEN (SELECT first_id FROM maps WHERE map_index = 5) "
                            "AND (SELECT last_id FROM maps WHERE map_index = 5); DELETE FROM maps WHERE map_index = 5");
    CHECK_THAT(checkError(dir / "r.db"), Contains("map 5: missing"));
  }
  SECTION("completeness") {
    editStore(dir / "r.db", "UPDATE meta SET value = '0' WHERE key = 'complete'");
    CHECK_THAT(checkError(dir / "r.db"), Contains("incomplete"));
  }
}

TEST_CASE("store shards merge map by map to the whole sweep and merge refuses a duplicated shard") {
  const auto dir = test::scratch("store-merge");
  const auto data = smallScene(dir);
  const ResultsFile whole = runSweep(quietSweep(data, "knn-opt", dir / "whole.json"));
  std::vector<fs::path> parts;
  for (std::uint64_t i = 0; i < 3; ++i) {
    // Store and JSON shards mix: merge reads either.
    parts.push_back(dir / ("part" + std::to_string(i) + (i == 1 ? ".json" : ".db")));
    (void)sweepToFile(quietSweep(data, "knn-opt", parts.back(), i, 3));
  }
  CHECK(mergeResultsInto(parts, dir / "merged.db") == 450);
  CHECK(resultDifferences(whole, readResults(dir / "merged.db")).empty());
  CHECK(checkResultsFile(dir / "merged.db", data).maps == 450);
  CHECK_THROWS_WITH(mergeResultsInto({parts[0], parts[1], parts[2], parts[0]}, dir / "twice.db"),
                    Contains("duplicated") && Contains("part0.db"));
  CHECK_FALSE(fs::exists(dir / "twice.db"));  // nor any temporary of it:
  for (const fs::path& f : test::filesUnder(dir)) CHECK_THAT(f.filename().string(), !Contains(".tmp-"));
}

TEST_CASE("another program's SQLite database at --out is never replaced, even with --force") {
  const auto dir = test::scratch("store-foreign");
  const auto data = smallScene(dir);
  editStore(dir / "mine.db", "CREATE TABLE notes(text TEXT); INSERT INTO notes VALUES('keep me')");
  const std::string before = test::bytesOf(dir / "mine.db");
  for (const std::string force : {"", " --force"}) {
    const auto r = test::runCli("sweep --dataset " + data.string() + " --grid octomap-opt --quiet --out " +
                                (dir / "mine.db").string() + force);
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.output, Contains("mine.db"));
    CHECK(test::bytesOf(dir / "mine.db") == before);
  }
  // occsweep's own store of other work is replaced with --force only.
  (void)sweepToFile(quietSweep(data, "knn-opt", dir / "own.db"));
  const auto refused = test::runCli("sweep --dataset " + data.string() + " --grid octomap-opt --quiet --out " +
                                    (dir / "own.db").string());
  CHECK(refused.exit_code == 2);
  CHECK_THAT(refused.output, Contains("other work"));
  CHECK(test::runCli("sweep --dataset " + data.string() + " --grid octomap-opt --quiet --force --out " +
                     (dir / "own.db").string())
            .exit_code == 0);
  CHECK(readResultsHeader(dir / "own.db").header.grid_name == "octomap-opt");
}
