// The results store (docs/results-format.md, "Results store"): the same numbers as JSON, byte-identical export,
// a kill loses at most the open transaction and resumes, a hand edit is caught, and a user's database is never
// replaced.
#include <catch2/catch.hpp>

#include <algorithm>
#include <atomic>
#include <csignal>
#include <functional>
#include <set>
#include <fstream>
#include <sstream>
#include <thread>

#include <sqlite3.h>
#include <fcntl.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

#include "occsweep/sweeps/merge.hpp"
#include "occsweep/sweeps/results_export.hpp"
#include "occsweep/sweeps/results_store.hpp"
#include "occsweep/sweeps/results_verify.hpp"
#include "occsweep/sweeps/sweep.hpp"
#include "small_scene.hpp"
#include "test_helpers.hpp"

using namespace occsweep;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {

const fs::path kGolden = occsweep::test::sourceTree() / "results" / "builtin";

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
  const std::string cli = occsweep::test::builtCli();
  const pid_t child = ::fork();
  if (child == 0) {
    ::execl(cli.c_str(), cli.c_str(), "sweep", "--dataset", data.c_str(), "--grid", "reduction", "--out", out.c_str(),
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
    CHECK(header.starts_with("dataset,point_cloud_set,dataset_hash,method,grid,truth,id,map_index,"));
    CHECK(last.starts_with(g.header.dataset_name + "," + pointCloudSetOf(g.header) + "," + g.header.dataset_hash + "," + g.header.method + "," +
                           g.header.grid_name + ",full," + key));
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
  SECTION("a second region row") {
    // A new store's schema refuses it (the combinations view would list every threshold twice)...
    sqlite3* db = nullptr;
    REQUIRE(sqlite3_open((dir / "r.db").c_str(), &db) == SQLITE_OK);
    CHECK(sqlite3_exec(db, "INSERT INTO region(region, truth) SELECT region, truth FROM region", nullptr, nullptr,
                       nullptr) == SQLITE_CONSTRAINT);
    sqlite3_close(db);
    CHECK(checkError(dir / "r.db") == "passed");
    // ...and an older store's region without the constraint is refused by results check.
    editStore(dir / "r.db", "CREATE TABLE r2 AS SELECT region, truth FROM region;"
                            "DROP VIEW combinations; DROP TABLE region;"
                            "CREATE TABLE region(region INTEGER NOT NULL, truth INTEGER NOT NULL);"
                            "INSERT INTO region SELECT region, truth FROM r2; INSERT INTO region SELECT region, truth FROM r2;"
                            "DROP TABLE r2;"
                            "CREATE VIEW combinations AS SELECT t.id AS id, m.map_index AS map_index,"
                            " t.p_t_micro / 1e6 AS p_t, t.tp AS tp, t.fp AS fp, r.truth - t.tp AS fn,"
                            " r.region - r.truth - t.fp AS tn"
                            " FROM maps m JOIN thresholds t ON t.id BETWEEN m.first_id AND m.last_id, region r");
    CHECK_THAT(checkError(dir / "r.db"), Contains("r.db") && Contains("region: holds more than one row"));
  }
  SECTION("completeness") {
    editStore(dir / "r.db", "UPDATE meta SET value = '0' WHERE key = 'complete'");
    CHECK_THAT(checkError(dir / "r.db"), Contains("incomplete"));
  }
  SECTION("a column renamed, two swapped or one retyped in the schema SQLite keeps (the old binary passed it; readers "
          "go by position, a user's query by name)") {
    const std::string edit = GENERATE(as<std::string>{}, "'last_id INTEGER NOT NULL', 'last_il INTEGER NOT NULL'",
                                      "'auc_anchored REAL, auc_observed REAL', 'auc_observed REAL, auc_anchored REAL'",
                                      "'seconds REAL', 'seconds TEXT'");
    editStore(dir / "r.db", "PRAGMA writable_schema = ON; UPDATE sqlite_master SET sql = replace(sql, " + edit +
                            ") WHERE name = 'maps'");
    CHECK_THAT(checkError(dir / "r.db"), Contains("r.db") && Contains("maps: its columns are not occsweep's"));
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

namespace {

// One damaged or hand-edited results file of the corpus below: a name (in the failure message) and its path.
struct Damaged {
  std::string what;
  fs::path file;
  bool hand_edit = false;  ///< a claim changed on purpose: results check must refuse it (a flip may hit unused bytes)
};

// The index of the map of the highest AUC (the first of equals): the map a hand edit of the best changes.
std::uint64_t bestMapIndex(const ResultsFile& f) {
  const auto best = std::max_element(f.maps.begin(), f.maps.end(), [](const MapResult& a, const MapResult& b) {
    return a.area.anchored < b.area.anchored;
  });
  REQUIRE(best != f.maps.end());
  return best->map_index;
}

// `base` copied to `dir/name` and changed by `edit` (SQL run on a store, as a user's sqlite3 shell would).
fs::path copyOf(const fs::path& base, const fs::path& dir, const std::string& name) {
  const fs::path out = dir / name;
  fs::copy_file(base, out, fs::copy_options::overwrite_existing);
  return out;
}

// The region table of an older store, without the constraint that keeps it at one row: two rows.
const char* kSecondRegionRow =
    "CREATE TABLE r2(region INTEGER NOT NULL, truth INTEGER NOT NULL); INSERT INTO r2 SELECT region, truth FROM region;"
    "INSERT INTO r2 SELECT region, truth FROM region; DROP VIEW combinations; DROP TABLE region;"
    "ALTER TABLE r2 RENAME TO region; CREATE VIEW combinations AS SELECT t.id AS id, m.map_index AS map_index,"
    " t.p_t_micro / 1e6 AS p_t, t.tp AS tp, t.fp AS fp, r.truth - t.tp AS fn, r.region - r.truth - t.fp AS tn"
    " FROM maps m JOIN thresholds t ON t.id BETWEEN m.first_id AND m.last_id, region r";

// Hand edits of a store: each one a claim results check refuses (an AUC, a count, a row, a table, the header).
std::vector<Damaged> editedStores(const fs::path& base, const fs::path& dir, std::uint64_t best) {
  const std::string b = std::to_string(best);
  const std::string best_rows = "DELETE FROM thresholds WHERE id BETWEEN (SELECT first_id FROM maps WHERE map_index = " +
                                b + ") AND (SELECT last_id FROM maps WHERE map_index = " + b + "); ";
  const std::vector<std::pair<std::string, std::string>> edits = {
      {"auc-5", "UPDATE maps SET auc_anchored = 5.0 WHERE map_index = " + b},
      {"auc-inf", "UPDATE maps SET auc_anchored = 1e999 WHERE map_index = " + b},
      {"auc-negative", "UPDATE maps SET auc_anchored = -0.5 WHERE map_index = 1"},
      {"auc-observed", "UPDATE maps SET auc_observed = 0.123 WHERE map_index = 2"},
      {"best-map-deleted", best_rows + "DELETE FROM maps WHERE map_index = " + b},
      {"map-row-deleted", "DELETE FROM maps WHERE map_index = 5"},
      {"tp-plus-one", "UPDATE thresholds SET tp = tp + 1 WHERE id = 7"},
      {"fp-negative", "UPDATE thresholds SET fp = -3 WHERE id = 7"},
      {"tp-text", "UPDATE thresholds SET tp = 'x' WHERE id = 7"},
      {"p-t-moved", "UPDATE thresholds SET p_t_micro = p_t_micro + 1 WHERE id = 3"},
      {"region-two-rows", kSecondRegionRow},
      {"region-below-truth", "PRAGMA ignore_check_constraints = ON; UPDATE region SET region = truth - 1"},
      {"truth-plus-one", "UPDATE region SET truth = truth + 1"},
      {"region-negative", "PRAGMA ignore_check_constraints = ON; UPDATE region SET region = -5, truth = -9"},
      {"thresholds-dropped", "DROP TABLE thresholds"},
      {"region-dropped", "DROP TABLE region"},
      {"maps-dropped", "DROP VIEW combinations; DROP TABLE maps"},
      {"header-deleted", "DELETE FROM meta WHERE key = 'header'"},
      {"seconds-nan", "UPDATE meta SET value = 'nan' WHERE key = 'seconds'"},
      {"resolution-negative", "UPDATE meta SET value = json_set(value, '$.map.resolution', -0.1) WHERE key = 'header'"},
      {"map-seconds-negative", "UPDATE maps SET seconds = -1 WHERE map_index = 2"},
      // Old code: SQLite read text as 0 (or its numeric prefix) and every reader went on.
      {"map-seconds-text", "UPDATE maps SET seconds = 'abc' WHERE map_index = 2"},
      {"auc-text-prefix", "UPDATE maps SET auc_observed = '0.5abc' WHERE map_index = 2"},
      {"seconds-hex", "UPDATE meta SET value = '0x10' WHERE key = 'seconds'"},
      {"seconds-prefix", "UPDATE meta SET value = '1.5abc' WHERE key = 'seconds'"},
      {"incomplete", "UPDATE meta SET value = '0' WHERE key = 'complete'"},
      {"parameter-edited", "UPDATE maps SET p_m = p_m + 0.01 WHERE map_index = 1"},
      {"auc-points", "UPDATE maps SET auc_points = auc_points + 1 WHERE map_index = 2"},
      {"view-dropped", "DROP VIEW combinations"},
      {"view-redefined", "DROP VIEW combinations; CREATE VIEW combinations AS SELECT id, 0 AS map_index FROM thresholds"},
      {"extra-table", "CREATE TABLE notes(x)"},
      {"extra-trigger", "CREATE TRIGGER t AFTER INSERT ON maps BEGIN DELETE FROM thresholds; END"},
      {"trigger-named-maps", "CREATE TRIGGER maps AFTER INSERT ON maps BEGIN DELETE FROM thresholds; END"},
      {"map-engine-unknown", "UPDATE maps SET engine = 'fast' WHERE map_index = 1"},
      {"header-engine-unknown",
       "UPDATE meta SET value = json_set(value, '$.map.engine', 'fast', '$.map.engines', json_array('fast')) "
       "WHERE key = 'header'"},
  };
  std::vector<Damaged> out;
  for (const auto& [name, sql] : edits) {
    out.push_back({"store " + name, copyOf(base, dir, name + ".db"), true});
    editStore(out.back().file, sql);
  }
  return out;
}

// Truncations and seeded single-bit flips of `base` (a store or a JSON file).
std::vector<Damaged> damagedCopies(const fs::path& base, const fs::path& dir, std::size_t cuts, std::size_t flips,
                                   std::uint64_t seed) {
  const std::string bytes = test::bytesOf(base), ext = base.extension().string();
  std::vector<Damaged> out;
  for (std::size_t i = 1; i <= cuts; ++i) {
    const std::size_t size = bytes.size() * i / (cuts + 1);
    out.push_back({"cut to " + std::to_string(size) + " bytes", dir / ("cut" + std::to_string(size) + ext)});
    std::ofstream(out.back().file, std::ios::binary) << bytes.substr(0, size);
  }
  SplitMix64 rng(seed);
  for (std::size_t i = 0; i < flips; ++i) {
    std::string flipped = bytes;
    const std::size_t at = std::size_t(rng.next() % bytes.size());
    flipped[at] = char(flipped[at] ^ (1 << (rng.next() % 8)));
    out.push_back({"bit flip at " + std::to_string(at), dir / ("flip" + std::to_string(i) + ext)});
    std::ofstream(out.back().file, std::ios::binary) << flipped;
  }
  return out;
}

// Hand edits of a JSON results file, each through nlohmann so the file stays JSON.
std::vector<Damaged> editedJson(const fs::path& base, const fs::path& dir) {
  const nlohmann::json j = nlohmann::json::parse(test::bytesOf(base));
  const std::vector<std::pair<std::string, std::function<void(nlohmann::json&)>>> edits = {
      {"tp", [](nlohmann::json& f) { f["maps"][3]["thresholds"][1]["tp"] = f["maps"][3]["thresholds"][1]["tp"].get<int>() + 1; }},
      {"tn", [](nlohmann::json& f) { f["maps"][3]["thresholds"][1]["tn"] = f["maps"][3]["thresholds"][1]["tn"].get<int>() + 1; }},
      {"auc", [](nlohmann::json& f) { f["maps"][4]["auc"]["anchored"] = 5.0; }},
      {"resolution", [](nlohmann::json& f) { f["map"]["resolution"] = -0.1; }},
      {"map-removed", [](nlohmann::json& f) { f["maps"].erase(2); }},
      {"map-twice", [](nlohmann::json& f) { f["maps"].push_back(f["maps"][0]); }},
      {"seconds", [](nlohmann::json& f) { f["seconds"] = -1.0; }},
      {"map-seconds", [](nlohmann::json& f) { f["maps"][1]["seconds"] = -2.0; }},
      {"incomplete", [](nlohmann::json& f) { f["complete"] = false; }},
      {"auc-points", [](nlohmann::json& f) { f["maps"][2]["auc"]["points"] = f["maps"][2]["auc"]["points"].get<int>() + 1; }},
      {"engine-unknown", [](nlohmann::json& f) { f["map"]["engine"] = "fast", f["map"]["engines"] = {"fast"}; }},
      {"engine-mismatch", [](nlohmann::json& f) { f["map"]["engine"] = "mixed"; }},
  };
  std::vector<Damaged> out;
  for (const auto& [name, edit] : edits) {
    nlohmann::json e = j;
    edit(e);
    out.push_back({"JSON " + name, dir / ("edited-" + name + ".json"), true});
    std::ofstream(out.back().file) << e.dump(1) << '\n';
  }
  return out;
}

// Every command that reads results, run on `file` (`good` where a second file is needed): the command line of each.
std::vector<std::string> readersOf(const fs::path& file, const fs::path& good, const fs::path& dir) {
  const std::string f = test::shellQuoted(file), out = (dir / "reader-out").string();
  return {"compare " + f,
          "merge " + f + " --out " + out + ".db",
          "merge " + f + " --out " + out + ".json",
          "results export " + f + " --out " + out + ".csv",
          "results export " + f + " --out " + out + ".db",
          "results export " + f + " --out " + out + ".json",
          "plot params " + f + " --out " + out + ".png --json " + out + ".plot.json",
          "results diff " + test::shellQuoted(good) + " " + f};
}

// A fresh scratch folder `name` with the small scene's octomap-opt sweep in both formats, r.db and r.json.
fs::path sweptBothWays(const std::string& name) {
  const auto dir = test::scratch(name);
  const auto data = smallScene(dir);
  (void)sweepToFile(quietSweep(data, "octomap-opt", dir / "r.db"));
  (void)sweepToFile(quietSweep(data, "octomap-opt", dir / "r.json"));
  return dir;
}

}  // namespace

TEST_CASE("every damaged or edited results file results check refuses, every reader of results refuses too") {
  const fs::path dir = sweptBothWays("store-corpus");
  const std::uint64_t best = bestMapIndex(readResults(dir / "r.json"));
  const fs::path corpus = dir / "corpus";
  fs::create_directories(corpus);
  std::vector<Damaged> files = editedStores(dir / "r.db", corpus, best);
  for (auto& d : damagedCopies(dir / "r.db", corpus, 8, 12, 11)) files.push_back(d);
  for (auto& d : damagedCopies(dir / "r.json", corpus, 6, 6, 12)) files.push_back(d);
  for (auto& d : editedJson(dir / "r.json", corpus)) files.push_back(d);
  // The readers accept both good files: a refusal below is the file's, not the command line's.
  for (const fs::path& good : {dir / "r.db", dir / "r.json"})
    for (const std::string& reader : readersOf(good, dir / "r.json", dir)) {
      for (const char* ext : {".json", ".db", ".csv", ".plot.json", ".png"}) fs::remove(dir / ("reader-out" + std::string(ext)));
      const auto r = test::runCli(reader);
      INFO(reader << "\n" << r.output);
      CHECK(r.exit_code == 0);
    }
  std::size_t refused = 0;
  for (const Damaged& d : files) {
    const auto check = test::runCli("results check " + test::shellQuoted(d.file));
    if (check.exit_code == 0) {
      INFO(d.what << ": results check accepted a hand edit");
      CHECK_FALSE(d.hand_edit);
      continue;  // a flip in unused bytes: a file as good as the original
    }
    ++refused;
    INFO(d.what << ": " << d.file.filename() << "\nresults check: " << check.output);
    CHECK(check.exit_code == 2);
    const std::string bytes = test::bytesOf(d.file);
    for (const std::string& reader : readersOf(d.file, dir / "r.json", corpus)) {
      const auto r = test::runCli(reader);
      INFO(reader << "\n" << r.output);
      CHECK(r.exit_code == 2);
      CHECK_THAT(r.output, Contains(d.file.filename().string()));
      for (const fs::path& left : test::filesUnder(corpus)) CHECK_THAT(left.string(), !Contains("reader-out"));
      CHECK(test::bytesOf(d.file) == bytes);  // a reader never changes the file it refuses (no journal rolled in)
    }
  }
  WARN(refused << " of " << files.size() << " damaged files refused by results check and by every reader");
  CHECK(refused >= 50);
}

namespace {

// What every reader says of the good store `store` beside which a file stands at `store-journal`: each exits 2 naming
// the journal with `advice`, never blaming the store, and leaves the journal as it was.
void checkReadersNameTheJournal(const fs::path& store, const fs::path& good, const fs::path& dir,
                                const std::string& advice) {
  const fs::path journal = store.string() + "-journal";
  const std::string bytes = test::bytesOf(journal);
  std::vector<std::string> readers = readersOf(store, good, dir);
  readers.push_back("results check " + test::shellQuoted(store));
  for (const std::string& reader : readers) {
    const auto r = test::runCli(reader);
    INFO(reader << "\n" << r.output);
    CHECK(r.exit_code == 2);
    CHECK_THAT(test::joinedLines(r.output), Contains(journal.string() + ": ") && Contains(advice));
    CHECK_THAT(r.output, !Contains("not an occsweep results store"));
    CHECK(test::bytesOf(journal) == bytes);
  }
}

}  // namespace

TEST_CASE("a file at a store's journal name is named by every reader, which never blames the store") {
  // Old binary: every reader opened the good store read-only, SQLite took the file for the journal of an
  // interrupted write it could not roll back, and each said "attempt to write a readonly database (not an occsweep
  // results store?)" of the store.
  const fs::path dir = sweptBothWays("store-journal-beside");
  const fs::path journal = dir / "r.db-journal";
  SECTION("a user's file at SQLite's reserved name") {
    std::ofstream(journal) << "my notes, not SQLite's\n";
    checkReadersNameTheJournal(dir / "r.db", dir / "r.json", dir, "move it away");
    fs::remove(journal);
  }
  SECTION("SQLite's own journal of a write that was killed") {
    const pid_t writer = ::fork();
    if (writer == 0) {  // a program writing the store, killed before its commit: its pages spilled to the file
      sqlite3* db = nullptr;
      sqlite3_open((dir / "r.db").c_str(), &db);
      sqlite3_exec(db, "PRAGMA cache_size = 1; BEGIN; DELETE FROM thresholds; DELETE FROM maps;", nullptr, nullptr,
                   nullptr);
      ::_exit(0);
    }
    int status = -1;
    REQUIRE(::waitpid(writer, &status, 0) == writer);
    REQUIRE(status == 0);
    REQUIRE(fs::file_size(journal) > 0);
    checkReadersNameTheJournal(dir / "r.db", dir / "r.json", dir, "roll it back by opening the store once for writing");
    editStore(dir / "r.db", "PRAGMA quick_check");  // what the message says: SQLite rolls the write back
    CHECK_FALSE(fs::exists(journal));
  }
  CHECK(checkError(dir / "r.db") == "passed");
}

namespace {

// The sweep command of the tests below, into `out` (a name in `dir`), --force optional.
std::string sweepInto(const fs::path& data, const fs::path& out, const std::string& more = "") {
  return "sweep --dataset " + test::shellQuoted(data) + " --grid octomap-opt --quiet --out " + test::shellQuoted(out) +
         more;
}

}  // namespace

TEST_CASE("a user's file, a symbolic link or a foreign database at a sweep's partial name is never touched") {
  // Old binary: a user's r.json.partial.jsonl was overwritten and then deleted, a symbolic link there written
  // through, and a user's non-SQLite file (or a SQLite file without tables) at r.db.partial deleted.
  const auto dir = test::scratch("store-partial-owner");
  const auto data = smallScene(dir);
  editStore(dir / "theirs.sqlite", "CREATE TABLE notes(text TEXT); INSERT INTO notes VALUES('keep me')");
  editStore(dir / "empty.sqlite", "PRAGMA user_version = 7");  // SQLite, no table
  std::ofstream(dir / "notes.txt") << "my notes, not occsweep's\n";
  const std::vector<std::pair<std::string, fs::path>> users = {
      {"text", dir / "notes.txt"}, {"database", dir / "theirs.sqlite"}, {"database without tables", dir / "empty.sqlite"}};
  for (const std::string out : {"r.json", "r.db"}) {
    const fs::path partial = dir / (out + (out == "r.json" ? ".partial.jsonl" : ".partial"));
    for (const auto& [what, file] : users)
      for (const bool link : {false, true})
        for (const std::string force : {"", " --force"}) {
          INFO(out << ": a " << (link ? "symbolic link to a " : "") << what << force);
          fs::remove(partial);
          if (link) fs::create_symlink(file, partial);
          else fs::copy_file(file, partial);
          const std::string before = test::bytesOf(file);
          const auto r = test::runCli(sweepInto(data, dir / out, force));
          INFO(r.output);
          CHECK(r.exit_code == 2);
          CHECK_THAT(r.output, Contains(partial.filename().string()) && Contains("never"));
          CHECK(fs::is_symlink(fs::symlink_status(partial)) == link);
          CHECK(test::bytesOf(partial) == before);
          CHECK(test::bytesOf(file) == before);
          CHECK_FALSE(fs::exists(dir / out));
        }
    // The same sweep's complete output is there: the partial name is not occsweep's, so it stays too.
    fs::remove(partial);
    REQUIRE(test::runCli(sweepInto(data, dir / out)).exit_code == 0);
    fs::copy_file(dir / "notes.txt", partial);
    const auto again = test::runCli(sweepInto(data, dir / out));
    CHECK(again.exit_code == 0);
    CHECK(test::bytesOf(partial) == test::bytesOf(dir / "notes.txt"));
    fs::remove(partial);
    fs::remove(dir / out);
  }
}

namespace {

// `occsweep ARGS` started in the background (its output into `log`), without waiting: its process id.
pid_t startCli(const std::string& args, const fs::path& log, const fs::path& cwd = ".") {
  const std::string line = "cd " + test::shellQuoted(cwd) + " && exec " + test::shellQuoted(test::cliUnderTest()) + " " + args + " > " +
                           test::shellQuoted(log) + " 2>&1";
  return test::startShell(line);
}

// The exit code of a started command; -signal when a signal ended it.
int exitOf(pid_t child) {
  int status = 0;
  ::waitpid(child, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
}

// Every name in `dir` but `keep`: what a command left beside its target.
std::vector<std::string> besides(const fs::path& dir, const std::set<std::string>& keep) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir))
    if (!keep.count(e.path().filename().string())) out.push_back(e.path().filename().string());
  return out;
}

}  // namespace

TEST_CASE("two sweeps into one store: one writes it, the other stops with another occsweep is writing it") {
  // Old binary: both ran into SQLite's internals ("already exists", "database is locked"), often both failing.
  const auto dir = test::scratch("store-two-writers");
  const auto data = smallScene(dir);
  // The direct engine on one thread: about 0.5 s of mapping, longer than the seeded gap between the two starts.
  const std::string sweep = sweepInto(data, dir / "r.db", " --engine direct --threads 1");
  SplitMix64 rng(21);
  for (int race = 0; race < 20; ++race) {
    INFO("race " << race);
    fs::remove(dir / "r.db");
    const pid_t first = startCli(sweep, dir / "first.log");
    std::this_thread::sleep_for(std::chrono::milliseconds(rng.next() % 120));
    const pid_t second = startCli(sweep, dir / "second.log");
    const int a = exitOf(first), b = exitOf(second);
    const std::string loser = test::bytesOf(dir / (a == 0 ? "second.log" : "first.log"));
    INFO("first: " << a << " " << test::bytesOf(dir / "first.log") << "second: " << b << " " << test::bytesOf(dir / "second.log"));
    CHECK(std::min(a, b) == 0);
    CHECK(std::max(a, b) == 2);
    CHECK_THAT(loser, Contains("another occsweep is writing") && Contains("r.db.partial"));
    CHECK(checkError(dir / "r.db") == "passed");
    CHECK(besides(dir, {"scene3", "r.db", "first.log", "second.log"}).empty());
  }
}

TEST_CASE("merge and results export into a store killed at random moments leave nothing beside the target") {
  // Old binary: a SIGINT or SIGTERM during a transaction left .M.db.tmp-PID-journal behind for good.
  const auto dir = test::scratch("store-killed-writers");
  const auto data = smallScene(dir);
  for (std::uint64_t i = 0; i < 2; ++i)
    (void)sweepToFile(quietSweep(data, "reduction", dir / ("s" + std::to_string(i) + ".db"), i, 2));
  (void)sweepToFile(quietSweep(data, "reduction", dir / "whole.db"));
  const std::set<std::string> inputs = {"scene3", "s0.db", "s1.db", "whole.db", "log"};
  const std::vector<std::string> commands = {"merge s0.db s1.db --out m.db", "results export whole.db --out m.db"};
  SplitMix64 rng(22);
  for (const std::string& command : commands) {
    const auto started = std::chrono::steady_clock::now();
    REQUIRE(exitOf(startCli(command, dir / "log", dir)) == 0);  // how long it takes: the kills fall within
    const auto took = std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - started);
    fs::remove(dir / "m.db");
    for (int kill = 0; kill < 20; ++kill) {
      INFO(command << ", kill " << kill);
      const pid_t child = startCli(command, dir / "log", dir);
      std::this_thread::sleep_for(std::chrono::milliseconds(rng.next() % std::uint64_t(took.count() + 1)));
      ::kill(child, kill % 2 ? SIGTERM : SIGINT);
      const int code = exitOf(child);
      INFO("exit " << code << ": " << test::bytesOf(dir / "log"));
      // A signal after the commit (the rename done) ends the command with 128 + signal beside a complete store:
      // m.db may stand whatever the exit code, but only whole (results check below), and must when it exited 0.
      std::set<std::string> keep = inputs;
      keep.insert("m.db");
      if (code == 0) CHECK(fs::exists(dir / "m.db"));
      const std::vector<std::string> left = besides(dir, keep);
      std::string names;
      for (const std::string& name : left) names += " " + name;
      INFO("left beside it:" << names);
      CHECK(left.empty());
      if (fs::exists(dir / "m.db")) CHECK(checkError(dir / "m.db") == "passed");
      for (const std::string& name : left) fs::remove(dir / name);  // each kill counted on its own
      fs::remove(dir / "m.db");
    }
  }
}

TEST_CASE("a grid of no combination is refused before anything is written") {
  // Old binary: exit 0 and a results file (JSON or store) that results check refuses (grid.combinations 0).
  const auto dir = test::scratch("store-empty-grid");
  const auto data = smallScene(dir);
  // p_m <= 0.2 < p_min: OctoMap's relation p_m >= p_min (docs/grids.md) leaves no combination.
  std::ofstream(dir / "empty.json") << R"({"name": "empty", "method": "octomap", "parameters": {"p_max": {"value": 0.98},
    "p_min": {"value": 0.3}, "p_h": {"min": 0.5, "max": 0.98, "step": 0.12}, "p_m": {"min": 0.02, "max": 0.2, "step": 0.12},
    "p_t": {"step": 0.12}}})";
  for (const std::string out : {"e.json", "e.db"}) {
    const auto r = test::runCli("sweep --dataset " + test::shellQuoted(data) + " --grid " +
                                test::shellQuoted(dir / "empty.json") + " --quiet --out " + test::shellQuoted(dir / out));
    INFO(r.output);
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.output, Contains("empty.json") && Contains("no combination"));
    CHECK(besides(dir, {"scene3", "empty.json"}).empty());
  }
}

TEST_CASE("a partial output locked by another process stops the sweep, and resumes once it is released") {
  // Old binary: no lock; two sweeps into one output wrote one partial output at once.
  const auto dir = test::scratch("store-partial-locked");
  const auto data = smallScene(dir);
  for (const std::string out : {"r.json", "r.db"}) {
    INFO(out);
    const bool store = out == "r.db";
    const fs::path partial = dir / (out + (store ? ".partial" : ".partial.jsonl"));
    REQUIRE(test::runCli(sweepInto(data, dir / out)).exit_code == 0);
    if (store) {
      fs::rename(dir / out, partial);  // occsweep's own store of this work: what a sweep resumes
    } else {
      std::ofstream(partial) << toJson(readResultsHeader(dir / out).header).dump() << '\n';  // a log with no map yet
      fs::remove(dir / out);
    }
    const int fd = ::open(partial.c_str(), O_RDONLY);
    REQUIRE(fd >= 0);
    REQUIRE(::flock(fd, LOCK_EX | LOCK_NB) == 0);  // as a running sweep holds it
    const auto refused = test::runCli(sweepInto(data, dir / out, " --force"));
    INFO(refused.output);
    CHECK(refused.exit_code == 2);
    CHECK_THAT(refused.output, Contains("another occsweep is writing") && Contains(partial.filename().string()));
    CHECK(fs::exists(partial));
    CHECK_FALSE(fs::exists(dir / out));
    ::close(fd);
    const auto resumed = test::runCli(sweepInto(data, dir / out));
    INFO(resumed.output);
    CHECK(resumed.exit_code == 0);
    CHECK(checkError(dir / out) == "passed");
    CHECK_FALSE(fs::exists(partial));
  }
}

TEST_CASE("a mixed-engine JSON results file exported or merged into a store passes results check") {
  // Previous code: the store's map rows said "mixed" (a JSON file records no engine per map), which results check then
  // refused as an engine the header does not name.
  const auto dir = test::scratch("store-mixed-engines");
  const auto data = smallScene(dir);
  (void)sweepToFile(quietSweep(data, "octomap-opt", dir / "r.json"));
  nlohmann::json j = nlohmann::json::parse(test::bytesOf(dir / "r.json"));
  j["map"]["engine"] = "mixed";  // as a sweep resumed under the other engine writes it
  j["map"]["engines"] = {"direct", "replay"};
  std::ofstream(dir / "mixed.json") << j.dump(1) << '\n';
  REQUIRE(checkError(dir / "mixed.json") == "passed");
  for (const std::string command : {"results export mixed.json --out e.db", "merge mixed.json --out m.db"}) {
    INFO(command);
    const auto r = test::runIn(dir, command);
    INFO(r.output);
    REQUIRE(r.exit_code == 0);
  }
  CHECK(checkError(dir / "e.db") == "passed");
  CHECK(checkError(dir / "m.db") == "passed");
}

TEST_CASE("compare and map --from read only what they checked while a store is swapped at its name") {
  // A store and two hand edits of it, renamed in turn onto one name while the readers run: the best map's AUC set to
  // 0.99 (compare reads a store's maps without their counts, so only the check derives the AUC again), and its p_u
  // set to 0.99, a value the grid does not hold (only the check against the grid catches it). Each reader either
  // refuses an edit (exit 2) or prints the true best map: never an AUC of 0.99 (compare printed it when it checked a
  // file by name and then opened it again), p_u=0.99, or counts that differ (map --from).
  const auto dir = test::scratch("store-swap");
  const auto data = smallScene(dir);
  (void)sweepToFile(quietSweep(data, "octomap-opt", dir / "oct.db"));
  (void)sweepToFile(quietSweep(data, "knn-opt", dir / "good.db"));
  const std::string where = " WHERE map_index = " + std::to_string(bestMapIndex(readResults(dir / "good.db")));
  const std::vector<std::pair<std::string, std::string>> edits = {{"auc.db", "UPDATE maps SET auc_anchored = 0.99" + where},
                                                                  {"p_u.db", "UPDATE maps SET p_u = 0.99" + where}};
  for (const auto& [name, sql] : edits) {
    fs::copy_file(dir / "good.db", dir / name);
    editStore(dir / name, sql);
    REQUIRE(test::runCli("results check " + test::shellQuoted(dir / name)).exit_code == 2);
  }
  fs::copy_file(dir / "good.db", dir / "knn.db");
  std::atomic<bool> stop = false;
  std::thread swapper([&] {
    for (std::uint64_t i = 0; !stop; ++i) {  // a fresh copy each time: rename moves the inode a reader may hold
      const fs::path from = dir / (i % 2 ? "good.db" : edits[i / 2 % 2].first), next = dir / "next.db";
      std::error_code ec;
      fs::copy_file(from, next, fs::copy_options::overwrite_existing, ec);
      if (!ec) fs::rename(next, dir / "knn.db", ec);
    }
  });
  const std::string q = test::shellQuoted(dir);
  const std::vector<std::string> readers = {
      "compare " + q + "/oct.db " + q + "/knn.db",
      "map --dataset " + test::shellQuoted(data) + " --from " + q + "/knn.db --best --force --out " + q + "/best.ot"};
  std::size_t refused = 0, read = 0;
  for (int run = 0; run < 100; ++run)
    for (const std::string& reader : readers) {
      const auto r = test::runCli(reader);
      INFO(reader << "\n" << r.output);
      CHECK_THAT(r.output, !Contains("0.9900") && !Contains("AUC 0.99") && !Contains("p_u=0.99") && !Contains("counts differ"));
      CHECK((r.exit_code == 0 || r.exit_code == 2));
      ++(r.exit_code == 0 ? read : refused);
    }
  stop = true;
  swapper.join();
  WARN(read << " reads, " << refused << " refusals of an edit, of " << 2 * 100);
  CHECK(read + refused == 2 * 100);
}
