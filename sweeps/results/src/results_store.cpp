// The results store on SQLite (docs/results-format.md, "Results store"). Schema, version 1:
//   meta(key, value)        format, version, header (the JSON header of a results file), complete, seconds
//   region(region, truth)   one row: TP+FP+FN+TN and TP+FN, the same for every combination of the file (stores
//                           created now also have a column `one`, unique and 1: a second row is refused)
//   maps(map_index, first_id, last_id, <one column per parameter>, auc_anchored, auc_observed, auc_points,
//        seconds, engine)
//   thresholds(id, p_t_micro, tp, fp)   FN and TN follow from region (why: 100 MB for 3.2 M combinations)
//   combinations            a view with every column of a JSON threshold, for queries
#include "occsweep/sweeps/results_store.hpp"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <initializer_list>
#include <ostream>
#include <limits>
#include <set>
#include <stdexcept>
#include <vector>

#include <sqlite3.h>

#include "occsweep/core/limits.hpp"
#include "occsweep/core/method_registry.hpp"
#include "occsweep/sweeps/results_verify.hpp"
#include "occsweep/io/output_target.hpp"
#include "occsweep/io/temporaries.hpp"

namespace occsweep {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr const char* kStoreFormat = "occsweep-results-store";
constexpr int kStoreVersion = 1;
constexpr std::streamoff kApplicationIdOffset = 68;  // SQLite's file header: 4 bytes, big-endian
constexpr std::size_t kMapColumns = 3;  // map_index, first_id, last_id: then the parameters
// Every table a store has (docs/results-format.md, "Results store"): a store missing one is refused by name.
constexpr const char* kTables[] = {"meta", "region", "maps", "thresholds"};
// The view a user queries (docs/results-format.md, "Results store"): its SQL as every store since the first holds it.
constexpr const char* kCombinationsView =
    "CREATE VIEW combinations AS SELECT t.id AS id, m.map_index AS map_index, t.p_t_micro / 1e6 AS p_t,"
    " t.tp AS tp, t.fp AS fp, r.truth - t.tp AS fn, r.region - r.truth - t.fp AS tn"
    " FROM maps m JOIN thresholds t ON t.id BETWEEN m.first_id AND m.last_id, region r";

// How long a statement waits for another connection's lock before it fails (docs/results-format.md, "Reading a
// store while a sweep writes it"): a reader's transaction blocks the sweep's commit, and a commit blocks readers,
// each for milliseconds in normal use.
constexpr int kBusyTimeoutMs = 60'000;

[[noreturn]] void fail(const fs::path& file, const std::string& what) {
  throw std::runtime_error(file.string() + ": " + what);
}

// SQLite's message for the last error, with what a lock held too long means for the user.
std::string errorText(sqlite3* db) {
  std::string why = sqlite3_errmsg(db);
  if (sqlite3_errcode(db) == SQLITE_BUSY)
    why += " (another program held a lock on it for more than " + std::to_string(kBusyTimeoutMs / 1000) + " s)";
  if (sqlite3_extended_errcode(db) == SQLITE_READONLY_DBMOVED)
    why = "it was moved, renamed or deleted while occsweep was writing it (what stands at its name now is left as "
          "it is)";
  return why;
}

// A failed statement: a full disk is an OutputError naming the file the user knows, as every failed write is
// (docs/io.md, "Outputs and --force"); anything else is SQLite's message.
[[noreturn]] void failStatement(const fs::path& file, sqlite3* db) {
  if (sqlite3_errcode(db) == SQLITE_FULL) throw OutputError(writeFailure(file, ENOSPC));
  fail(file, "results store: " + errorText(db));
}

// sqlite3_open_v2 with the busy timeout set; the handle, even on failure, is the caller's to close. Without SQLite's
// own mutex: one thread uses a connection at a time (a sweep's counting threads append under StoreWriter's lock), and
// locking it for every column read took a fifth of `compare`'s time on a 3.2 M-combination store.
int openDatabase(const fs::path& file, int flags, sqlite3** db) {
  const int rc = sqlite3_open_v2(file.c_str(), db, flags | SQLITE_OPEN_NOMUTEX, nullptr);
  if (rc == SQLITE_OK) sqlite3_busy_timeout(*db, kBusyTimeoutMs);
  return rc;
}

// One prepared statement; reset on every bind so it can be reused.
class Statement {
 public:
  Statement(sqlite3* db, const std::string& sql, const fs::path& file) : db_(db), file_(file) {
    if (sqlite3_prepare_v2(db, sql.c_str(), int(sql.size()), &s_, nullptr) != SQLITE_OK)
      fail(file, "results store: " + errorText(db) + " (not an occsweep results store?)");
  }
  ~Statement() { sqlite3_finalize(s_); }
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;

  Statement& bind(int i, std::int64_t v) { return check(sqlite3_bind_int64(s_, i, v)); }
  Statement& bind(int i, double v) {
    return check(std::isfinite(v) ? sqlite3_bind_double(s_, i, v) : sqlite3_bind_null(s_, i));
  }
  Statement& bind(int i, const std::string& v) {
    return check(sqlite3_bind_text(s_, i, v.data(), int(v.size()), SQLITE_TRANSIENT));
  }
  /// True while a row is ready.
  bool step() {
    const int rc = sqlite3_step(s_);
    if (rc == SQLITE_ROW) return true;
    if (rc != SQLITE_DONE) failStatement(file_, db_);
    return false;
  }
  void run() {
    step();
    sqlite3_reset(s_);
    sqlite3_clear_bindings(s_);
  }
  [[nodiscard]] bool isNull(int c) const { return sqlite3_column_type(s_, c) == SQLITE_NULL; }
  /// A stored integer, asked before the column is read (reading converts it).
  [[nodiscard]] bool isInteger(int c) const { return sqlite3_column_type(s_, c) == SQLITE_INTEGER; }
  /// A stored number (or NULL): SQLite would read text such as 'abc' or '1.5abc' as 0 or 1.5 without a word.
  [[nodiscard]] bool isNumberOrNull(int c) const { return sqlite3_column_type(s_, c) != SQLITE_TEXT &&
                                                          sqlite3_column_type(s_, c) != SQLITE_BLOB; }
  [[nodiscard]] std::int64_t integer(int c) const { return sqlite3_column_int64(s_, c); }
  [[nodiscard]] double real(int c) const {
    return isNull(c) ? std::numeric_limits<double>::quiet_NaN() : sqlite3_column_double(s_, c);
  }
  [[nodiscard]] std::string text(int c) const {
    const auto* t = sqlite3_column_text(s_, c);
    return t ? reinterpret_cast<const char*>(t) : "";
  }
  [[nodiscard]] int columns() const { return sqlite3_column_count(s_); }

 private:
  Statement& check(int rc) {
    if (rc != SQLITE_OK) failStatement(file_, db_);
    return *this;
  }
  sqlite3* db_;
  sqlite3_stmt* s_ = nullptr;
  const fs::path& file_;
};

// A parameter's column name: its name quoted as an SQL identifier.
std::string column(const std::string& name) {
  std::string q = "\"";
  for (char ch : name) q.append(ch == '"' ? "\"\"" : std::string(1, ch));
  return q + "\"";
}

// The maps table's parameter columns of `layout`, as create() declares them: `, "p_h" REAL, "k" INTEGER`.
std::string parameterColumns(const ParameterLayout& layout) {
  std::string params;
  for (std::size_t i = 0; i < layout.names.size(); ++i)
    params += ", " + column(layout.names[i]) + (layout.integer[i] ? " INTEGER" : " REAL");
  return params;
}

// Each table of a store of `layout`'s parameters (kTables' order), as create() makes it: SQLite keeps the statement's
// text in sqlite_master, so a reader compares it whole (a renamed or retyped column is another schema).
std::vector<std::string> tableStatements(const ParameterLayout& layout) {
  return {"CREATE TABLE meta(key TEXT PRIMARY KEY, value TEXT NOT NULL) WITHOUT ROWID",
          "CREATE TABLE region(region INTEGER NOT NULL, truth INTEGER NOT NULL CHECK(truth >= 0 AND truth <= region),"
          " one INTEGER NOT NULL DEFAULT 1 UNIQUE CHECK(one = 1))",
          "CREATE TABLE maps(map_index INTEGER PRIMARY KEY, first_id INTEGER NOT NULL, last_id INTEGER NOT NULL" +
              parameterColumns(layout) +
              ", auc_anchored REAL, auc_observed REAL, auc_points INTEGER NOT NULL, seconds REAL NOT NULL,"
              " engine TEXT NOT NULL)",
          "CREATE TABLE thresholds(id INTEGER PRIMARY KEY, p_t_micro INTEGER NOT NULL, tp INTEGER NOT NULL,"
          " fp INTEGER NOT NULL)"};
}

Fixed fixedOf(double v) { return std::llround(v * double(kFixedScale)); }

// What a map row must hold whatever the detail read: an AUC is a share of the unit square (or null: undefined),
// a time finite and >= 0. A Summary read (compare) prints them as stored.
void requireStoredNumbers(const MapResult& m, const fs::path& file, const std::string& where) {
  for (const double auc : {m.area.anchored, m.area.observed})
    if (!std::isnan(auc) && !(auc >= 0 && auc <= 1)) fail(file, where + ": auc must be in [0, 1] or null");
  if (!std::isfinite(m.seconds) || m.seconds < 0) fail(file, where + ": seconds must be a finite number >= 0");
}

// A regular file that begins with SQLite's rollback-journal header (sqlite.org/fileformat.html, "The Rollback
// Journal"): what a kill of a write leaves beside a store.
bool isRollbackJournal(const fs::path& journal) {
  static constexpr unsigned char kJournalMagic[8] = {0xd9, 0xd5, 0x05, 0xf9, 0x20, 0xa1, 0x63, 0xd7};
  std::error_code ec;
  if (!fs::is_regular_file(fs::symlink_status(journal, ec))) return false;
  char head[sizeof kJournalMagic] = {};
  std::ifstream in(journal, std::ios::binary);
  in.read(head, sizeof head);
  return in.gcount() == sizeof head && std::memcmp(head, kJournalMagic, sizeof head) == 0;
}

}  // namespace

struct ResultsStore::Connection {
  fs::path file;
  sqlite3* db = nullptr;
  ResultsHeader header;
  bool complete = false;
  double seconds = 0.0;
  std::uint64_t region = 0, truth = 0;
  bool has_region = false;

  explicit Connection(fs::path f) : file(std::move(f)) {}
  ~Connection() { sqlite3_close(db); }

  void exec(const std::string& sql) {
    char* error = nullptr;
    if (sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &error) != SQLITE_OK) {
      sqlite3_free(error);
      failStatement(file, db);
    }
  }
  void setMeta(const std::string& key, const std::string& value) {
    Statement(db, "INSERT OR REPLACE INTO meta(key, value) VALUES(?, ?)", file).bind(1, key).bind(2, value).run();
  }
  std::string meta(const std::string& key) {
    Statement s(db, "SELECT value FROM meta WHERE key = ?", file);
    s.bind(1, key);
    if (!s.step()) fail(file, "meta." + key + ": is missing");
    return s.text(0);
  }
  // The one region row (none before the first map): TP+FP+FN+TN and TP+FN of every combination. A second row
  // would make the `combinations` view list every threshold twice; older stores have no constraint against it.
  void readRegion() {
    Statement s(db, "SELECT region, truth, typeof(region) = 'integer' AND typeof(truth) = 'integer' FROM region", file);
    has_region = s.step();
    if (!has_region) return;
    const std::int64_t r = s.integer(0), t = s.integer(1);
    if (!s.integer(2) || t < 0 || r < t || std::uint64_t(r) > kMaxRegionVoxels)
      fail(file, "region: region and truth must be integers with 0 <= truth <= region <= 2^48");
    region = std::uint64_t(r), truth = std::uint64_t(t);
    if (s.step()) fail(file, "region: holds more than one row (a store has exactly one region)");
  }
  // A read-only connection (every reader's) reads nothing of a store while a file stands at STORE-journal that
  // SQLite takes for the journal of an interrupted write: it cannot roll it back. The journal is named, not the store
  // blamed (docs/results-format.md, "Reading").
  void requireNoJournalInTheWay() {
    if (sqlite3_exec(db, "PRAGMA schema_version", nullptr, nullptr, nullptr) == SQLITE_OK ||
        sqlite3_errcode(db) == SQLITE_BUSY)
      return;
    const fs::path journal = file.string() + "-journal";
    std::error_code ec;
    if (!fs::exists(fs::symlink_status(journal, ec))) return;  // the reads that follow say what is wrong
    if (isRollbackJournal(journal))
      fail(journal, "the rollback journal of a write to " + file.string() + " that was interrupted (a program "
                    "writing the store was killed): SQLite reads nothing of the store until it is rolled back, which "
                    "occsweep, reading stores read-only, never does; roll it back by opening the store once for "
                    "writing (sqlite3 " + file.string() + " 'PRAGMA quick_check'), then run again");
    fail(journal, "stands at the name SQLite reserves for the rollback journal of " + file.string() + ", and is not "
                  "one: SQLite takes it for an interrupted write and reads nothing of the store (opened for writing, "
                  "it would delete the file); move it away, then run again");
  }
  // The schema as occsweep writes it: its four tables, the `combinations` view with its own SQL, and no other table,
  // view or trigger (each would change what a reader or a resumed sweep sees); an index a user adds for their own
  // queries changes nothing and is allowed.
  void requireTables() {
    for (const char* table : kTables) {
      Statement s(db, "SELECT count(*) FROM sqlite_master WHERE type = 'table' AND name = ?", file);
      s.bind(1, std::string(table));
      if (!s.step() || s.integer(0) != 1) fail(file, std::string(table) + ": table is missing (not a whole results store)");
    }
    Statement view(db, "SELECT sql FROM sqlite_master WHERE type = 'view' AND name = 'combinations'", file);
    if (!view.step() || view.text(0) != kCombinationsView)
      fail(file, "combinations: the view is missing or not occsweep's (edited by hand?)");
    // By type and name: a trigger may share a table's name (SQLite keeps their names apart).
    Statement other(db, "SELECT type, name FROM sqlite_master WHERE type != 'index' AND NOT (type = 'table' AND "
                        "name IN ('meta', 'region', 'maps', 'thresholds')) AND NOT (type = 'view' AND name = "
                        "'combinations')", file);
    if (other.step())
      fail(file, other.text(0) + " " + other.text(1) + ": not part of a results store (added by hand?)");
  }
  // Each table's columns as occsweep declares them (tableStatements): readers go by column position, a user's query
  // by name, so a column renamed or retyped (edited by hand, a flipped bit) would mean one thing to each.
  void requireTableStatements(const std::vector<std::string>& statements) {
    // A store written before the region's one-row constraint: its region table as made then (readRegion refuses a
    // second row of it).
    const std::string region_before_constraint = "CREATE TABLE region(region INTEGER NOT NULL, truth INTEGER NOT NULL)";
    for (std::size_t i = 0; i < statements.size(); ++i) {
      Statement s(db, "SELECT sql FROM sqlite_master WHERE type = 'table' AND name = ?", file);
      s.bind(1, std::string(kTables[i]));
      const bool found = s.step();
      const std::string sql = found ? s.text(0) : "";
      const bool older_region = std::string(kTables[i]) == "region" && sql == region_before_constraint;
      if (!found || (sql != statements[i] && !older_region))
        fail(file, std::string(kTables[i]) + ": its columns are not occsweep's (renamed or retyped by hand?)");
    }
  }
};

ResultsStore::ResultsStore(std::unique_ptr<Connection> c) : c_(std::move(c)) {}
ResultsStore::ResultsStore(ResultsStore&&) noexcept = default;
ResultsStore& ResultsStore::operator=(ResultsStore&&) noexcept = default;
ResultsStore::~ResultsStore() = default;

bool isResultsStore(const fs::path& file) {
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) return false;  // a FIFO is never opened here (it would block): the JSON reader refuses it by name
  std::ifstream in(file, std::ios::binary);
  char head[16] = {};
  return in.read(head, sizeof head) && std::memcmp(head, "SQLite format 3", 16) == 0;
}

namespace {
bool walModeFile(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  unsigned char head[20] = {};
  return in.read(reinterpret_cast<char*>(head), sizeof head) && (head[18] == 2 || head[19] == 2);
}
}  // namespace

bool isOccsweepStore(const fs::path& file) {
  std::error_code ec;
  if (fs::is_symlink(fs::symlink_status(file, ec)) || !isResultsStore(file)) return false;
  std::ifstream in(file, std::ios::binary);
  unsigned char id[4] = {};
  in.seekg(kApplicationIdOffset);
  if (!in.read(reinterpret_cast<char*>(id), 4)) return false;
  return (std::uint32_t(id[0]) << 24 | std::uint32_t(id[1]) << 16 | std::uint32_t(id[2]) << 8 | id[3]) ==
         kStoreApplicationId;
}

ResultsStore ResultsStore::create(const fs::path& file, const ResultsHeader& header, StoreUse use) {
  auto c = std::make_unique<Connection>(file);
  std::error_code ec;
  if (fs::exists(fs::symlink_status(file)) && fs::file_size(file, ec) != 0) fail(file, "results store: already exists");
  // A temporary is the empty file its claim made (OutputFile, RegisteredTemporary): opened, never created, so that one
  // an interrupt has removed is not made again before the exit.
  const int create = use == StoreUse::Temporary ? 0 : SQLITE_OPEN_CREATE;
  if (openDatabase(file, SQLITE_OPEN_READWRITE | create, &c->db) != SQLITE_OK)
    fail(file, std::string("cannot create: ") + (c->db ? sqlite3_errmsg(c->db) : "out of memory"));
  // Journal off would lose the crash safety of a batch; WAL needs a second file beside it. The default rollback
  // journal is kept, with synchronous NORMAL: a kill loses at most the open transaction. A temporary renamed into
  // place when complete keeps its journal in memory: a kill removes the temporary, and no journal file is left
  // beside it (docs/io.md, "Outputs and --force").
  if (use == StoreUse::Temporary) c->exec("PRAGMA journal_mode = MEMORY");
  // application_id marks the file as occsweep's within the schema's transaction: only a file carrying it is ever
  // resumed, replaced or removed (docs/results-format.md, "Results store").
  std::string schema;
  for (const std::string& table : tableStatements(header.parameters)) schema += table + ";";
  c->exec("PRAGMA synchronous = NORMAL; BEGIN; PRAGMA application_id = " + std::to_string(kStoreApplicationId) + ";" +
          schema + std::string(kCombinationsView) + ";");
  c->header = header;
  c->setMeta("format", kStoreFormat);
  c->setMeta("version", std::to_string(kStoreVersion));
  c->setMeta("header", toJson(header).dump());
  c->setMeta("complete", "0");
  c->setMeta("seconds", "0");
  c->exec("COMMIT");  // the schema and header at once: a kill leaves a store, or a file without tables
  return ResultsStore(std::move(c));
}

ResultsStore ResultsStore::open(const fs::path& file, bool writable) {
  auto c = std::make_unique<Connection>(file);
  if (!isResultsStore(file)) fail(file, "not a results store (no SQLite header)");
  // Bytes 18 and 19 of the SQLite header are 2 in WAL mode, which occsweep never uses: opening such a file, even
  // read-only, would leave FILE-wal and FILE-shm beside it.
  if (walModeFile(file)) fail(file, "in SQLite's WAL journal mode, which no store occsweep writes uses (not opened)");
  const int flags = writable ? SQLITE_OPEN_READWRITE : SQLITE_OPEN_READONLY;
  if (openDatabase(file, flags, &c->db) != SQLITE_OK)
    fail(file, std::string("cannot open: ") + (c->db ? sqlite3_errmsg(c->db) : "out of memory"));
  if (!writable) c->requireNoJournalInTheWay();  // a writer rolls a journal back (requireOnlyRollbackJournalBeside)
  c->requireTables();
  if (c->meta("format") != kStoreFormat) fail(file, std::string("meta.format: must be \"") + kStoreFormat + "\"");
  if (c->meta("version") != std::to_string(kStoreVersion)) fail(file, "meta.version: unsupported store version");
  json header;
  const std::string header_text = c->meta("header");
  checkLimit(file.string() + ": meta.header: bytes of JSON", header_text.size(), limits().json_bytes,
             "--max-json-bytes");
  try {
    header = json::parse(header_text);
  } catch (const json::exception&) {
    fail(file, "meta.header: is not JSON");
  }
  c->header = parseHeader(header, file.string() + ": meta.header");
  c->complete = c->meta("complete") == "1";
  try {
    const std::string text = c->meta("seconds");
    std::size_t used = 0;
    c->seconds = std::stod(text, &used);
    if (used != text.size() || text.find_first_of("xXpP") != std::string::npos) throw std::invalid_argument(text);
  } catch (const std::exception&) {
    fail(file, "meta.seconds: must be a number");
  }
  if (!std::isfinite(c->seconds) || c->seconds < 0) fail(file, "meta.seconds: must be a finite number >= 0");
  if (c->header.parameters.names.empty()) {
    // A method this program has not registered: its parameters are the maps table's columns (in order).
    Statement s(c->db, "SELECT name, type FROM pragma_table_info('maps') ORDER BY cid", file);
    for (std::size_t i = 0; s.step(); ++i)
      if (i >= kMapColumns && !s.text(0).starts_with("auc_") && s.text(0) != "seconds" && s.text(0) != "engine") {
        c->header.parameters.names.push_back(s.text(0));
        c->header.parameters.integer.push_back(s.text(1) == "INTEGER");
      }
  }
  c->requireTableStatements(tableStatements(c->header.parameters));
  c->readRegion();
  return ResultsStore(std::move(c));
}

void ResultsStore::verifyIntegrity() const {
  // quick_check reads every page: a truncated or bit-flipped file is refused before its rows are believed.
  Statement s(c_->db, "PRAGMA quick_check", c_->file);
  while (s.step())
    if (s.text(0) != "ok") fail(c_->file, "damaged SQLite file (PRAGMA quick_check: " + s.text(0) + ")");
}

const ResultsHeader& ResultsStore::header() const { return c_->header; }
bool ResultsStore::complete() const { return c_->complete; }
double ResultsStore::seconds() const { return c_->seconds; }
std::uint64_t ResultsStore::truthVoxels() const { return c_->truth; }

std::uint64_t ResultsStore::mapCount() const {
  Statement s(c_->db, "SELECT count(*) FROM maps", c_->file);
  s.step();
  return std::uint64_t(s.integer(0));
}

void ResultsStore::append(const std::vector<MapResult>& maps, const std::string& engine) {
  Connection& c = *c_;
  const ParameterLayout& layout = c.header.parameters;
  std::string map_sql = "INSERT INTO maps VALUES(?, ?, ?";
  for (std::size_t i = 0; i < layout.names.size(); ++i) map_sql += ", ?";
  map_sql += ", ?, ?, ?, ?, ?)";
  Statement map_row(c.db, map_sql, c.file);
  Statement threshold_row(c.db, "INSERT INTO thresholds VALUES(?, ?, ?, ?)", c.file);
  c.exec("BEGIN");
  try {
    for (const MapResult& m : maps) {
      if (m.thresholds.empty()) fail(c.file, "map " + std::to_string(m.map_index) + ": has no threshold");
      for (const ThresholdResult& t : m.thresholds) {
        const ConfusionCounts& n = t.counts;
        const std::uint64_t region = n.tp + n.fp + n.fn + n.tn, truth = n.tp + n.fn;
        if (!c.has_region) {
          Statement(c.db, "INSERT INTO region(region, truth) VALUES(?, ?)", c.file).bind(1, std::int64_t(region)).bind(2, std::int64_t(truth)).run();
          c.region = region, c.truth = truth, c.has_region = true;
        }
        if (region != c.region || truth != c.truth)
          fail(c.file, "map " + std::to_string(m.map_index) + ": counts another region or truth than the maps "
                       "stored before (every map of a results file classifies the same voxels)");
        threshold_row.bind(1, std::int64_t(t.id)).bind(2, std::int64_t(t.p_t)).bind(3, std::int64_t(n.tp))
            .bind(4, std::int64_t(n.fp)).run();
      }
      map_row.bind(1, std::int64_t(m.map_index)).bind(2, std::int64_t(m.thresholds.front().id))
          .bind(3, std::int64_t(m.thresholds.back().id));
      const int n = int(layout.names.size());
      for (int i = 0; i < n; ++i) {
        const Fixed v = m.params.values.at(std::size_t(i));
        if (layout.integer[std::size_t(i)]) map_row.bind(4 + i, std::int64_t(v / kFixedScale));
        else map_row.bind(4 + i, toDouble(v));
      }
      map_row.bind(4 + n, m.area.anchored).bind(5 + n, m.area.observed).bind(6 + n, std::int64_t(m.area.points))
          .bind(7 + n, m.seconds).bind(8 + n, engine).run();
    }
    c.exec("COMMIT");
  } catch (...) {
    sqlite3_exec(c.db, "ROLLBACK", nullptr, nullptr, nullptr);
    if (c.has_region && mapCount() == 0) c.readRegion();  // the region row of a rolled-back first batch is gone
    throw;
  }
}

std::vector<std::uint64_t> ResultsStore::mapIndices() const {
  std::vector<std::uint64_t> out;
  Statement s(c_->db, "SELECT map_index FROM maps ORDER BY map_index", c_->file);
  while (s.step()) out.push_back(std::uint64_t(s.integer(0)));
  return out;
}

std::vector<std::string> ResultsStore::engineNames() const {
  std::vector<std::string> out;
  Statement s(c_->db, "SELECT DISTINCT engine FROM maps ORDER BY engine", c_->file);
  while (s.step()) out.push_back(s.text(0));
  return out;
}

void ResultsStore::finish(const ResultsHeader& header, double seconds) {
  Connection& c = *c_;
  c.exec("BEGIN");
  c.setMeta("header", toJson(header).dump());
  c.setMeta("seconds", json(seconds).dump());
  c.setMeta("complete", "1");
  c.exec("COMMIT");
  c.header = header;
  c.seconds = seconds;
  c.complete = true;
}

void ResultsStore::forEachMap(MapDetail detail, const MapVisitor& visit) const {
  const Connection& c = *c_;
  const ParameterLayout& layout = c.header.parameters;
  const int n_params = int(layout.names.size());
  Statement maps(c.db, "SELECT * FROM maps ORDER BY map_index", c.file);
  if (maps.columns() != int(kMapColumns) + n_params + 5)
    fail(c.file, "maps: has " + std::to_string(maps.columns()) + " columns, the header's method " + c.header.method +
                     " needs " + std::to_string(int(kMapColumns) + n_params + 5));
  std::unique_ptr<Statement> thresholds;
  if (detail == MapDetail::Full)
    thresholds = std::make_unique<Statement>(c.db, "SELECT id, p_t_micro, tp, fp FROM thresholds ORDER BY id", c.file);
  bool threshold_ready = thresholds && thresholds->step();
  while (maps.step()) {
    MapResult m;
    m.map_index = std::uint64_t(maps.integer(0));
    const std::string where = "maps row " + std::to_string(m.map_index);
    const std::uint64_t first = std::uint64_t(maps.integer(1)), last = std::uint64_t(maps.integer(2));
    for (int i = 0; i < n_params; ++i) {
      const int col = int(kMapColumns) + i;
      m.params.values.push_back(layout.integer[std::size_t(i)] ? Fixed(maps.integer(col)) * kFixedScale
                                                               : fixedOf(maps.real(col)));
    }
    const int a = int(kMapColumns) + n_params;
    for (int col = int(kMapColumns); col < a + 4; ++col)
      if (!maps.isNumberOrNull(col)) fail(c.file, where + ": column " + std::to_string(col + 1) + " must be a number");
    m.area = {maps.real(a), maps.real(a + 1), int(maps.integer(a + 2))};
    m.seconds = maps.real(a + 3);
    requireStoredNumbers(m, c.file, where);
    if (thresholds) {
      for (; threshold_ready && std::uint64_t(thresholds->integer(0)) <= last; threshold_ready = thresholds->step()) {
        const std::uint64_t id = std::uint64_t(thresholds->integer(0));
        if (id < first) fail(c.file, "thresholds row " + std::to_string(id) + ": belongs to no map");
        // Checked here, not by typeof() in the query: comparing its text for every row doubled the scan's time.
        if (!thresholds->isInteger(1) || !thresholds->isInteger(2) || !thresholds->isInteger(3))
          fail(c.file, "thresholds row " + std::to_string(id) + ": p_t_micro, tp and fp must be integers");
        const std::uint64_t tp = std::uint64_t(thresholds->integer(2)), fp = std::uint64_t(thresholds->integer(3));
        if (tp > c.truth || fp > c.region - c.truth)
          fail(c.file, "thresholds row " + std::to_string(id) + ": TP or FP larger than the region allows");
        m.thresholds.push_back({id, Fixed(thresholds->integer(1)), {tp, fp, c.truth - tp, c.region - c.truth - fp}});
      }
      if (m.thresholds.empty()) fail(c.file, where + ": has no threshold");
      const CurveArea derived = mapArea(m.thresholds);
      const auto agrees = [](double stored, double d) {
        return (std::isnan(stored) && std::isnan(d)) || std::abs(stored - d) <= 1e-12 * std::max(1.0, std::abs(d));
      };
      if (!agrees(m.area.anchored, derived.anchored) || !agrees(m.area.observed, derived.observed) ||
          m.area.points != derived.points)
        fail(c.file, where + ": auc does not match the counts it is derived from (edited by hand?)");
      m.area = derived;
    }
    visit(std::move(m));
  }
  if (threshold_ready) fail(c.file, "thresholds row " + std::to_string(thresholds->integer(0)) + ": belongs to no map");
}

namespace {
// Nothing may stand at any of SQLite's companion names `suffixes` beside `store`: SQLite would take it for the
// store's unfinished transaction (requireNoJournalBeside, requireOnlyRollbackJournalBeside).
void requireNothingBeside(const fs::path& store, std::initializer_list<const char*> suffixes) {
  for (const std::string suffix : suffixes) {
    const fs::path companion = store.string() + suffix;
    const char* kind = suffix == "-journal" ? "rollback journal" : suffix == "-wal" ? "write-ahead log" : "shared memory";
    std::error_code ec;
    if (fs::exists(fs::symlink_status(companion, ec)))
      throw OutputError(companion.string() + ": stands where SQLite keeps the " + kind + " of the store occsweep is "
                        "to write at " + store.string() + ", and would be taken for its unfinished transaction: "
                        "nothing was written; move it away, or choose another name");
  }
}
}  // namespace

void requireNoJournalBeside(const fs::path& store) { requireNothingBeside(store, {"-journal", "-wal", "-shm"}); }

void requireOnlyRollbackJournalBeside(const fs::path& store) {
  const fs::path journal = store.string() + "-journal";
  std::error_code ec;
  if (!fs::is_regular_file(fs::symlink_status(journal, ec))) return requireNoJournalBeside(store);
  if (!isRollbackJournal(journal))
    throw OutputError(journal.string() + ": is not a rollback journal SQLite wrote (no journal header), and SQLite "
                      "would take it for the unfinished transaction of the store occsweep is to resume at " +
                      store.string() + " and delete it: nothing was written; move it away");
  requireNothingBeside(store, {"-wal", "-shm"});  // a store occsweep writes never has a write-ahead log
}

void writeResultsStore(const ResultsFile& f, const fs::path& file) {
  requireNoJournalBeside(file);
  OutputFile out(file);  // its empty temporary becomes the store: removed on an error or an interrupt
  {
    ResultsStore store = ResultsStore::create(out.temporary(), f.header, StoreUse::Temporary);
    constexpr std::size_t kBatch = 4096;
    std::vector<MapResult> batch;
    for (const MapResult& m : f.maps) {
      batch.push_back(m);
      if (batch.size() == kBatch) store.append(batch, f.header.engine), batch.clear();
    }
    if (!batch.empty()) store.append(batch, f.header.engine);
    if (f.complete) store.finish(f.header, f.seconds);
  }
  out.commit();
}

}  // namespace occsweep
