// The ledger of temporaries (docs/robustness.md, "Ownership"): what proves a leftover temporary is occsweep's.
#include "occsweep/eval/ownership.hpp"
#include "occsweep/eval/fnv1a.hpp"
#include "occsweep/eval/process_stat.hpp"

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <set>
#include <random>
#include <sstream>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace occsweep {
namespace fs = std::filesystem;

namespace {

constexpr const char* kTemporaryMark = ".tmp-";
constexpr std::size_t kTokenDigits = 32;

std::string randomToken() {
  std::random_device device;  // /dev/urandom: a user cannot guess the name of a temporary not yet made
  std::string token;
  static constexpr char kHex[] = "0123456789abcdef";
  while (token.size() < kTokenDigits) {
    const unsigned bits = device();
    for (int i = 0; i < 8; ++i) token += kHex[(bits >> (4 * i)) & 15u];
  }
  return token;
}

// A process is named by its PID and its start time: a PID reused after a kill has another start time. "" when there
// is no such process.
std::string processIdentity(long pid) {
  const std::optional<ProcessStat> stat = processStat(pid);
  return stat ? std::to_string(pid) + " " + stat->start_time : "";
}

std::string firstLine(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  return line;
}

// Where PIDs mean something: the host, its boot (/proc/sys/kernel/random/boot_id) and the PID namespace. A ledger
// in a home folder shared by cluster nodes or containers holds records of processes this one cannot see.
struct Machine {
  std::string host, boot, pid_namespace;
};

const Machine& thisMachine() {
  static const Machine here = [] {
    char host[256] = {};
    ::gethostname(host, sizeof host - 1);
    std::error_code ec;
    const fs::path ns = fs::read_symlink("/proc/self/ns/pid", ec);
    return Machine{host, firstLine("/proc/sys/kernel/random/boot_id"), ns.string()};
  }();
  return here;
}

std::string machineLine(const Machine& m) { return m.host + " " + m.boot + " " + m.pid_namespace; }

// Where the entry `path` names sits, whatever way its path is spelt (through a symbolic link, `..`, relative): its
// folder's canonical path (links resolved) and the entry's name. `path` itself as spelt when the folder is gone.
fs::path canonicalEntry(const fs::path& path) {
  std::error_code ec;
  const fs::path absolute = fs::absolute(path, ec).lexically_normal();
  const fs::path folder = fs::canonical(absolute.parent_path(), ec);
  return ec ? absolute : folder / absolute.filename();
}

// A path as one line of a record: '\' and a line break escaped ("\\", "\n"), so that a folder or name holding a
// line break (a legal byte in a name) neither splits the record nor moves its other lines.
std::string recordLine(const fs::path& path) {
  std::string line;
  for (const char c : path.string()) line += c == '\\' ? "\\\\" : c == '\n' ? "\\n" : std::string(1, c);
  return line;
}

// recordLine read back. Any other '\' stays as it is: a record an older occsweep wrote unescaped reads the same
// unless its path held a '\' before an 'n' or another '\'.
fs::path recordPath(const std::string& line) {
  std::string path;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const bool escape = line[i] == '\\' && i + 1 < line.size() && (line[i + 1] == '\\' || line[i + 1] == 'n');
    path += escape ? (line[++i] == 'n' ? '\n' : '\\') : line[i];
  }
  return path;
}

// An entry's birth time as a record holds it, "-" where the file system keeps none (then the inode alone tells
// entries apart: docs/robustness.md, "Ownership").
std::string birthText(const struct statx& entry) {
  if ((entry.stx_mask & STATX_BTIME) == 0) return "-";
  return std::to_string(entry.stx_btime.tv_sec) + "." + std::to_string(entry.stx_btime.tv_nsec);
}

// Which entry `path` names: its canonicalEntry, and the folder's inode and birth time (statx), so that a folder
// removed and made again at the same path, even one that reuses the inode, is another folder. The device number is
// left out: NFS, btrfs and overlayfs give it out anew at each mount. One line, the path by its FNV-1a hash (a path
// may hold a line break). "" when the folder cannot be read.
std::string entryIdentity(const fs::path& path) {
  const fs::path entry = canonicalEntry(path);
  struct statx folder {};
  if (::statx(AT_FDCWD, entry.parent_path().c_str(), 0, STATX_INO | STATX_BTIME, &folder) != 0) return "";
  Fnv1a where;
  where.feed(entry.string());
  return std::to_string(folder.stx_ino) + " " + birthText(folder) + " " + where.hex();
}

// The entry at `path` itself (not what a link there points to), or, with a `descriptor`, the file it has open.
bool statEntry(const fs::path& path, int descriptor, unsigned fields, struct statx& out) {
  if (descriptor >= 0) return ::statx(descriptor, "", AT_EMPTY_PATH, fields, &out) == 0;
  return ::statx(AT_FDCWD, path.c_str(), AT_SYMLINK_NOFOLLOW, fields, &out) == 0;
}

// The entry itself: its inode and birth time. "" when it cannot be read.
std::string entryStamp(const fs::path& path, int descriptor = -1) {
  struct statx made {};
  if (!statEntry(path, descriptor, STATX_INO | STATX_BTIME, made)) return "";
  return std::to_string(made.stx_ino) + " " + birthText(made);
}

// The entry's stamp as the fifth line of its record holds it. "" when it cannot be read.
std::string madeIdentity(const fs::path& path, int descriptor = -1) {
  const std::string stamp = entryStamp(path, descriptor);
  return stamp.empty() ? "" : "made " + stamp;
}

constexpr unsigned kContentFields = STATX_TYPE | STATX_INO | STATX_BTIME | STATX_SIZE | STATX_MTIME;

// What stamps an entry made inside a temporary folder once it is whole (read with kContentFields): its entryStamp
// and, for a file, its size and modification time, so that bytes a user writes into it in place (`cp` over it, `>>`)
// make it theirs.
std::string contentStampOf(const struct statx& made) {
  std::string stamp = std::to_string(made.stx_ino);  // piece by piece: "a" + std::string trips GCC 12's -Wrestrict
  stamp += ' ';
  stamp += birthText(made);
  if (!S_ISREG(made.stx_mode)) return stamp;
  for (const std::string& field : {std::to_string(made.stx_size), std::to_string(made.stx_mtime.tv_sec)}) {
    stamp += ' ';
    stamp += field;
  }
  stamp += '.';
  stamp += std::to_string(made.stx_mtime.tv_nsec);
  return stamp;
}

std::string contentStamp(const fs::path& path, int descriptor = -1) {
  struct statx made {};
  return statEntry(path, descriptor, kContentFields, made) ? contentStampOf(made) : "";
}

// A made entry's stamp after occsweep's last write (recordMadeEntryWritten): its contentStamp and its status-change
// time, which no user can set (`cp -p` and `touch` set the modification time): on a file system without birth
// times, a copy restored at a reused inode is another entry.
std::string writtenStamp(const fs::path& path, int descriptor = -1) {
  struct statx made {};  // one read: the content and the change time of the same moment
  if (!statEntry(path, descriptor, kContentFields | STATX_CTIME, made)) return "";
  return contentStampOf(made) + " changed " + std::to_string(made.stx_ctime.tv_sec) + "." +
         std::to_string(made.stx_ctime.tv_nsec);
}

// An entry inside a temporary folder as its record names it: the FNV-1a hash of its path relative to the folder
// (one line whatever the name holds).
std::string contentKey(const fs::path& relative) {
  Fnv1a key;
  key.feed(relative.lexically_normal().string());
  return key.hex();
}

// `.NAME.tmp-PID-TOKEN` parsed: the PID and TOKEN, or pid -1.
struct TemporaryName {
  long pid = -1;
  std::string token;
};

// The part of an output's name its temporaries carry: the whole name, or as much of it as keeps the temporary
// within the file system's 255 bytes (NAME_MAX) beside a 9-digit PID and the token, so that a legal 255-byte
// output name still has a legal temporary.
std::string temporaryStem(const std::string& output_name) {
  constexpr std::size_t kRest = 1 + 5 + 9 + 1 + kTokenDigits;  // "." ".tmp-" PID "-" TOKEN
  return output_name.size() + kRest <= kFileNameMax ? output_name : output_name.substr(0, kFileNameMax - kRest);
}

TemporaryName parseTemporary(const std::string& component, const std::string& output_name) {
  std::string prefix = ".";  // piece by piece: "." + std::string trips GCC 12's -Wrestrict false positive
  prefix += temporaryStem(output_name);
  prefix += kTemporaryMark;
  if (!component.starts_with(prefix)) return {};
  const std::string rest = component.substr(prefix.size());
  const std::size_t dash = rest.find('-');
  if (dash == std::string::npos || dash == 0 || dash > 9 || rest.size() - dash - 1 != kTokenDigits) return {};
  if (rest.find_first_not_of("0123456789") < dash) return {};
  if (rest.find_first_not_of("0123456789abcdef", dash + 1) != std::string::npos) return {};
  return {std::stol(rest.substr(0, dash)), rest.substr(dash + 1)};
}

// A record: the process identity on the first line, the temporary's canonicalEntry on the second (where pruning looks
// for it, and what a person reading the ledger sees), the machine (machineLine) on the third, the temporary's
// entryIdentity on the fourth: what proves an entry is that temporary, with the made entry's madeIdentity on the
// fifth once it exists (recordTemporaryMade). A folder's record goes on with what the folder holds: `holds KEY`
// before an entry is made there, `made-in KEY STAMP` once it is (recordTemporaryContent).
struct LedgerRecord {
  std::string process;
  fs::path path;
  std::string machine, entry, made;
  std::set<std::string> holds;                 ///< contentKey of each entry named before it was made
  std::map<std::string, std::string> made_in;  ///< contentKey -> contentStamp of each entry once whole
};

std::optional<LedgerRecord> readRecord(const fs::path& ledger, const std::string& token) {
  std::ifstream in(ledger / token);
  LedgerRecord r;
  std::string path;
  if (!std::getline(in, r.process) || !std::getline(in, path) || !std::getline(in, r.machine)) return std::nullopt;
  std::getline(in, r.entry);  // "" in a record of an occsweep that kept no identity: it proves nothing
  r.path = recordPath(path);
  // "made" absent when a kill came between the making and its record, or from an older occsweep
  for (std::string line; std::getline(in, line);) {
    if (line.starts_with("made ")) r.made = line;
    if (line.starts_with("holds ")) r.holds.insert(line.substr(6));
    if (const std::size_t key_end = line.find(' ', 8); line.starts_with("made-in ") && key_end != std::string::npos)
      r.made_in[line.substr(8, key_end - 8)] = line.substr(key_end + 1);
  }
  return r;
}

// The process that made a record is gone: same host, and another boot, or the same boot and PID namespace and no
// process of that PID and start time (a PID reused since has another start time). A record of another host or
// PID namespace proves nothing either way: false.
bool recordedProcessGone(const LedgerRecord& r) {
  const Machine& here = thisMachine();
  std::istringstream fields(r.machine);
  Machine there;
  fields >> there.host >> there.boot >> there.pid_namespace;
  if (there.host != here.host) return false;
  if (there.boot != here.boot) return true;
  if (there.pid_namespace != here.pid_namespace) return false;
  std::istringstream process(r.process);
  long pid = 0;
  return process >> pid && processIdentity(pid) != r.process;
}

// A record that cannot be read this long after it was written was cut short by a kill while being written (a record
// is a few bytes, written at once). Dropping one only makes a temporary the user's, never the reverse.
constexpr auto kUnfinishedRecordAge = std::chrono::hours(1);

// Whether `record` was last written more than `age` ago.
bool recordAged(const fs::path& record, std::chrono::hours age) {
  std::error_code ec;
  const auto written = fs::last_write_time(record, ec);
  return !ec && fs::file_time_type::clock::now() - written > age;
}

bool unfinishedRecord(const fs::path& record) {
  return recordAged(record, kUnfinishedRecordAge);
}

// Drops records whose process is gone and whose temporary is no longer where it was made (removed by hand, its
// folder deleted or replaced, another entry put at its name), and records a kill cut short: what a kill leaves in
// the ledger when nothing writes that target again.
void pruneLedger(const fs::path& ledger) {
  std::error_code ec;
  for (fs::directory_iterator it(ledger, ec), end; !ec && it != end; it.increment(ec)) {
    const std::optional<LedgerRecord> r = readRecord(ledger, it->path().filename().string());
    std::error_code missing;
    if (!r) {
      if (unfinishedRecord(it->path())) fs::remove(it->path(), missing);
      continue;
    }
    if (!recordedProcessGone(*r)) continue;
    const bool still_there = fs::exists(fs::symlink_status(r->path, missing)) && entryIdentity(r->path) == r->entry &&
                             (r->made.empty() || madeIdentity(r->path) == r->made);
    if (!still_there) fs::remove(it->path(), missing);
  }
}

// The token of `entry` when it is a recorded temporary of `target` whose process is gone.
std::optional<std::string> staleRecord(const fs::path& entry, const fs::path& target);

}  // namespace

fs::path ownershipLedger() {
  if (const char* dir = std::getenv("OCCSWEEP_STATE_DIR"); dir && *dir) return fs::path(dir) / "temporaries";
  if (const char* dir = std::getenv("XDG_STATE_HOME"); dir && *dir) return fs::path(dir) / "occsweep/temporaries";
  if (const char* home = std::getenv("HOME"); home && *home) return fs::path(home) / ".local/state/occsweep/temporaries";
  return {};
}

TemporaryClaim claimTemporary(const fs::path& target) {
  TemporaryClaim c;
  c.token = randomToken();
  std::string name = ".";  // appended piece by piece: "." + std::string trips GCC 12's -Wrestrict false positive
  name += temporaryStem(target.filename().string());
  name += kTemporaryMark;
  name += std::to_string(::getpid());
  name += '-';
  name += c.token;
  c.path = target.parent_path() / name;
  const fs::path ledger = ownershipLedger();
  std::error_code ec;
  if (ledger.empty() || (fs::create_directories(ledger, ec), ec)) return c;
  const std::string identity = entryIdentity(c.path);
  if (identity.empty()) return c;  // its folder cannot be read: nothing would prove the temporary occsweep's later
  pruneLedger(ledger);
  std::ofstream out(ledger / c.token, std::ios::trunc);
  out << processIdentity(::getpid()) << '\n' << recordLine(canonicalEntry(c.path)) << '\n' << machineLine(thisMachine())
      << '\n' << identity << '\n';
  out.flush();
  c.recorded = bool(out);
  return c;
}

namespace {
// Appends a line to a live record; never creates one (an interrupt's cleaner may have released it meanwhile).
void appendToRecord(const TemporaryClaim& claim, const std::string& line) {
  const int fd = ::open((ownershipLedger() / claim.token).c_str(), O_WRONLY | O_APPEND | O_CLOEXEC);
  if (fd < 0) return;
  (void)!::write(fd, line.data(), line.size());
  ::close(fd);
}
}  // namespace

void recordTemporaryMade(const TemporaryClaim& claim) {
  if (!claim.recorded) return;
  const std::string made = madeIdentity(claim.path);
  if (!made.empty()) appendToRecord(claim, made + "\n");
}


void recordTemporaryContent(const TemporaryClaim& claim, const fs::path& relative) {
  if (claim.recorded) appendToRecord(claim, "holds " + contentKey(relative) + "\n");
}

void recordTemporaryContentMade(const TemporaryClaim& claim, const fs::path& relative) {
  if (!claim.recorded) return;
  const std::string stamp = contentStamp(claim.path / relative);
  if (!stamp.empty()) appendToRecord(claim, "made-in " + contentKey(relative) + " " + stamp + "\n");
}

void releaseTemporary(const TemporaryClaim& claim) {
  if (!claim.recorded) return;
  std::error_code ec;
  fs::remove(ownershipLedger() / claim.token, ec);
}

std::string outputNameOf(const std::string& component) {
  const std::size_t mark = component.rfind(kTemporaryMark);
  if (component.size() < 2 || component[0] != '.' || mark == std::string::npos || mark < 2) return component;
  const std::string name = component.substr(1, mark - 1);
  return parseTemporary(component, name).pid > 0 ? name : component;
}

bool isStaleTemporaryOf(const fs::path& entry, const fs::path& target) {
  return staleRecord(entry, target).has_value();
}

namespace {
// SQLite's rollback journal named after a temporary (`path-journal`: what a kill of a store being written there
// leaves), unless a link stands there (occsweep never makes one).
void removeJournalOf(const fs::path& path) noexcept {
  std::error_code ec;
  const fs::path journal = path.string() + "-journal";
  if (!fs::is_symlink(fs::symlink_status(journal, ec))) fs::remove(journal, ec);
}
}  // namespace

bool removeTemporaryEntry(const fs::path& path) noexcept {
  std::error_code ec;
  // occsweep never makes a temporary (or journal) that is a symbolic link: one there is the user's, and stays.
  if (fs::is_symlink(fs::symlink_status(path, ec))) return false;
  // A folder temporary of this run is removed as a whole (a killed run's only once emptied of what its record
  // proves: removeStaleEntry). Another thread of the same run may
  // still be making a file in it (an interrupt's cleaner runs beside the writer): removed again until the folder
  // itself is gone, which ends such a writer's creations (their folder no longer exists).
  for (int attempt = 0; attempt < 100; ++attempt) {
    ec.clear();
    fs::remove_all(path, ec);
    std::error_code gone;
    if (!fs::exists(fs::symlink_status(path, gone))) break;
  }
  removeJournalOf(path);
  return !ec;
}

namespace {
// An entry of a killed run's temporary folder is the run's when its record lists it: made (its inode and birth time
// the recorded ones) or, for the one entry a kill may have come to between the two lines, named before the making.
bool provenContent(const LedgerRecord& r, const fs::path& entry, const fs::path& relative) {
  const std::string key = contentKey(relative);
  if (const auto made = r.made_in.find(key); made != r.made_in.end()) return made->second == contentStamp(entry);
  return r.holds.contains(key);
}

// What emptying a killed run's temporary folder came to.
struct Emptied {
  bool foreign = false;  ///< an entry its record does not prove stays
  bool failed = false;   ///< a proven entry could not be read or removed (kept, for a later run to try again)
};

// Removes, deepest first, what `folder` holds that provenContent proves; a folder only once it is empty, and only a
// proven one is entered (a folder a user put at a recorded name is theirs, whatever it holds). Links are removed as
// entries, never followed.
void removeProvenContent(const LedgerRecord& r, const fs::path& root, const fs::path& folder, Emptied& result) {
  std::error_code ec;
  std::vector<fs::directory_entry> entries;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) entries.push_back(*it);
  if (ec) result.failed = true;
  for (const auto& e : entries) {
    std::error_code status_ec, removed;
    const bool is_folder = fs::is_directory(fs::symlink_status(e.path(), status_ec));
    if (!provenContent(r, e.path(), e.path().lexically_relative(root))) {
      result.foreign = true;
      continue;
    }
    Emptied inside;
    if (is_folder) removeProvenContent(r, root, e.path(), inside);
    result.foreign |= inside.foreign, result.failed |= inside.failed;
    if (!inside.foreign && !inside.failed && !fs::remove(e.path(), removed)) result.failed = true;
  }
}

// A killed run's temporary: a file as a whole; a folder with what its record proves occsweep made there, then the
// folder itself while empty (rmdir: an entry put there meanwhile stays). False when something could not be removed:
// the record stays for a later run. A folder holding entries its record does not prove is the user's from now on:
// kept, named in a warning, and true (the record goes).
bool removeStaleEntry(const fs::path& entry, const LedgerRecord& r) {
  std::error_code ec;
  const fs::file_status status = fs::symlink_status(entry, ec);
  if (!fs::is_directory(status) || fs::is_symlink(status)) return removeTemporaryEntry(entry);
  Emptied result;
  removeProvenContent(r, entry, entry, result);
  if (!result.foreign && !result.failed) {
    if (!fs::remove(entry, ec)) return false;
    removeJournalOf(entry);
    return true;
  }
  if (result.failed) return false;
  std::cerr << "occsweep: warning: kept " << entry.string() << ", a folder a killed occsweep left: it holds entries"
            << " occsweep cannot prove it made there (moved in since, or drawn by a figure script), which it leaves to"
            << " you; what it made there was removed (docs/robustness.md, \"Ownership\")\n";
  return true;
}
}  // namespace

bool removeStaleTemporary(const fs::path& entry, const fs::path& target) {
  const std::optional<std::string> token = staleRecord(entry, target);
  if (!token) return false;
  const std::optional<LedgerRecord> record = readRecord(ownershipLedger(), *token);
  std::error_code ec;
  if (record && removeStaleEntry(entry, *record)) fs::remove(ownershipLedger() / *token, ec);
  return true;
}

namespace {
std::optional<std::string> staleRecord(const fs::path& entry, const fs::path& target) {
  const TemporaryName t = parseTemporary(entry.filename().string(), target.filename().string());
  const fs::path ledger = ownershipLedger();
  if (t.pid <= 0 || ledger.empty()) return std::nullopt;
  const std::optional<LedgerRecord> record = readRecord(ledger, t.token);
  if (!record || record->entry.empty() || record->entry != entryIdentity(entry)) return std::nullopt;  // made elsewhere
  if (!record->made.empty() && record->made != madeIdentity(entry)) return std::nullopt;  // another entry put there
  if (!record->process.starts_with(std::to_string(t.pid) + " ")) return std::nullopt;
  if (!recordedProcessGone(*record)) return std::nullopt;  // it still runs, or runs where this process cannot see
  return t.token;
}
}  // namespace

namespace {
// A text output's record (recordTextOutput), a file of four lines: its entryIdentity, size, FNV-1a hash of its bytes
// and canonicalEntry. Named by the hash of the identity, so that any spelling of the output's path finds it.
struct TextOutputRecord {
  fs::path file;  ///< the record's own file in the ledger
  std::string identity, size, hash, path;  ///< path: recordLine of its canonicalEntry
};

fs::path outputsLedger() {
  const fs::path ledger = ownershipLedger();
  return ledger.empty() ? ledger : ledger.parent_path() / "outputs";
}

std::optional<TextOutputRecord> readTextOutputRecord(const fs::path& record) {
  std::ifstream in(record);
  TextOutputRecord r{record, {}, {}, {}, {}};
  if (!std::getline(in, r.identity) || !std::getline(in, r.size) || !std::getline(in, r.hash)) return std::nullopt;
  std::getline(in, r.path);  // "" in a record of an occsweep that named outputs by path (legacyRecordHolds)
  return r;
}

// What `file` is now, as a record would hold it, with the name of its record.
std::optional<TextOutputRecord> textOutputNow(const fs::path& file) {
  const fs::path outputs = outputsLedger();
  std::error_code ec;
  if (outputs.empty() || !fs::is_regular_file(fs::symlink_status(file, ec))) return std::nullopt;
  const std::string identity = entryIdentity(file);
  if (identity.empty()) return std::nullopt;
  Fnv1a name, content;
  name.feed(identity);
  try {
    content.feedFile(file);
  } catch (const std::exception&) {
    return std::nullopt;
  }
  return TextOutputRecord{outputs / name.hex(), identity, std::to_string(fs::file_size(file, ec)), content.hex(),
                          recordLine(canonicalEntry(file))};
}

// A record an occsweep before entry identities wrote: named by the hash of the output's absolute path, whose first
// line is that path. It proves the same bytes at that same spelling, as it did then.
bool legacyRecordHolds(const fs::path& file, const TextOutputRecord& now) {
  std::error_code ec;
  const std::string absolute = fs::absolute(file, ec).lexically_normal().string();
  Fnv1a name;
  name.feed(absolute);
  const std::optional<TextOutputRecord> old = readTextOutputRecord(outputsLedger() / name.hex());
  return old && old->identity == absolute && old->size == now.size && old->hash == now.hash;
}

// Drops the records of outputs no longer where they were written, or no longer that entry (removed, replaced).
void pruneTextOutputs(const fs::path& outputs) {
  std::error_code ec;
  for (fs::directory_iterator it(outputs, ec), end; !ec && it != end; it.increment(ec)) {
    const std::optional<TextOutputRecord> r = readTextOutputRecord(it->path());
    std::error_code missing;
    if (!r) {
      if (unfinishedRecord(it->path())) fs::remove(it->path(), missing);  // it proves nothing: the file is the user's
      continue;
    }
    const fs::path where = r->path.empty() ? fs::path(r->identity) : recordPath(r->path);  // a legacy record: its path
    const bool gone = !fs::exists(fs::symlink_status(where, missing));
    if (gone || (!r->path.empty() && entryIdentity(where) != r->identity)) fs::remove(it->path(), missing);
  }
}
}  // namespace

void recordTextOutput(const fs::path& file) {
  const std::optional<TextOutputRecord> r = textOutputNow(file);
  if (!r) return;
  std::error_code ec;
  fs::create_directories(r->file.parent_path(), ec);
  pruneTextOutputs(r->file.parent_path());
  std::ofstream(r->file, std::ios::trunc) << r->identity << '\n' << r->size << '\n' << r->hash << '\n' << r->path
                                          << '\n';
}

bool isRecordedTextOutput(const fs::path& file) {
  const std::optional<TextOutputRecord> now = textOutputNow(file);
  if (!now) return false;
  const std::optional<TextOutputRecord> recorded = readTextOutputRecord(now->file);
  if (!recorded) return legacyRecordHolds(file, *now);
  return recorded->identity == now->identity && recorded->size == now->size && recorded->hash == now->hash;
}

namespace {
// A made entry's record (claimMadeEntry, recordMadeEntry), four lines: its entryIdentity, its madeIdentity ("" in a
// claim), its canonicalEntry and the machine (machineLine); named by the hash of the identity, in the ledger's
// `made/` folder.
struct MadeEntryRecord {
  std::string identity, made, path, machine;  ///< path: recordLine of its canonicalEntry
    std::string written;  ///< its writtenStamp after occsweep's last write (recordMadeEntryWritten); "" before
};

fs::path madeEntryRecord(const fs::path& entry) {
  const fs::path ledger = ownershipLedger();
  const std::string identity = ledger.empty() ? "" : entryIdentity(entry);
  if (identity.empty()) return {};
  Fnv1a name;
  name.feed(identity);
  return ledger.parent_path() / "made" / name.hex();
}

std::optional<MadeEntryRecord> readMadeEntryRecord(const fs::path& record) {
  std::ifstream in(record);
  MadeEntryRecord r;
  if (!std::getline(in, r.identity) || !std::getline(in, r.made) || !std::getline(in, r.path) ||
      !std::getline(in, r.machine))
    return std::nullopt;
  std::getline(in, r.written);
  return r;
}

// How long the record of an entry whose whole folder is missing is kept (pruneMadeEntries).
constexpr auto kMissingFolderRecordAge = std::chrono::hours(24 * 30);

// Drops this machine's records whose entry is gone or is another entry now (what a kill, or a user's removal, leaves
// behind), a claim once an hour old without its entry, and records a kill cut short. Another machine's (a home folder
// shared by cluster nodes) are its own to prune: their paths may be local to it.
void pruneMadeEntries(const fs::path& folder) {
  std::error_code ec;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    const std::optional<MadeEntryRecord> r = readMadeEntryRecord(it->path());
    std::error_code removed, status;
    if (r && r->machine != machineLine(thisMachine())) continue;
    const fs::path entry = r ? recordPath(r->path) : fs::path();
    // An entry whose whole folder is missing (a disk unmounted, a plan folder moved away for a while) keeps its record
    // until it is old: dropped now, the folder's logs would be unproven when it comes back.
    if (r && !fs::exists(entry.parent_path(), status) && !recordAged(it->path(), kMissingFolderRecordAge)) continue;
    const bool gone = !r || !fs::exists(fs::symlink_status(entry, status));
    const bool stale = !r || r->made.empty() ? gone && unfinishedRecord(it->path()) : madeIdentity(entry) != r->made;
    if (stale) fs::remove(it->path(), removed);
  }
}

void writeMadeEntryRecord(const fs::path& entry, const std::string& made, const std::string& written = "") {
  const fs::path record = madeEntryRecord(entry);
  if (record.empty()) return;
  std::error_code ec;
  fs::create_directories(record.parent_path(), ec);
  // Once a process: a run-local of thousands of tasks writes four records a task (its log and its running marker,
  // each claimed and then stamped), and a walk of the folder for each would cost the square of the tasks.
  static std::atomic<bool> pruned{false};
  if (!pruned.exchange(true)) pruneMadeEntries(record.parent_path());
  // Written beside it and renamed over it: a record is rewritten as the entry is claimed, made and written, and an
  // interrupt's exit (or a kill) in the middle of a rewrite must leave the last whole one, not a cut one that proves
  // nothing (a cut `.tmp-PID` file is dropped by the pruning an hour on).
  const fs::path whole = record.string() + ".tmp-" + std::to_string(::getpid());
  {
    std::ofstream out(whole, std::ios::trunc);
    out << entryIdentity(entry) << '\n' << made << '\n' << recordLine(canonicalEntry(entry)) << '\n'
        << machineLine(thisMachine()) << '\n' << written << '\n';
    if (!out.flush()) return;
  }
  fs::rename(whole, record, ec);
}

// A claim proves an entry born within moments of it (a kill came between the making and its stamp), never one put
// at that name later.
constexpr auto kClaimMoments = std::chrono::seconds(1);

bool bornJustAfter(const fs::path& entry, const fs::path& record) {
  struct statx born {}, claimed {};
  if (::statx(AT_FDCWD, entry.c_str(), AT_SYMLINK_NOFOLLOW, STATX_BTIME, &born) != 0 ||
      (born.stx_mask & STATX_BTIME) == 0 || ::statx(AT_FDCWD, record.c_str(), 0, STATX_MTIME, &claimed) != 0)
    return false;
  using std::chrono::nanoseconds, std::chrono::seconds;
  const auto birth = seconds(born.stx_btime.tv_sec) + nanoseconds(born.stx_btime.tv_nsec);
  const auto claim = seconds(claimed.stx_mtime.tv_sec) + nanoseconds(claimed.stx_mtime.tv_nsec);
  return birth + seconds(1) >= claim && birth <= claim + kClaimMoments;
}
}  // namespace

void claimMadeEntry(const fs::path& entry) { writeMadeEntryRecord(entry, ""); }

void recordMadeEntry(const fs::path& entry) {
  const std::string made = madeIdentity(entry);
  if (!made.empty()) writeMadeEntryRecord(entry, made);
}

void recordMadeEntryWritten(const fs::path& entry) {
  const fs::path record = madeEntryRecord(entry);
  const std::optional<MadeEntryRecord> r = record.empty() ? std::nullopt : readMadeEntryRecord(record);
  const std::string made = madeIdentity(entry), written = writtenStamp(entry);
  if (r && !made.empty() && r->made == made && !written.empty()) writeMadeEntryRecord(entry, made, written);
}

bool isRecordedMadeEntry(const fs::path& entry, int descriptor) {
  const fs::path record = madeEntryRecord(entry);
  const std::optional<MadeEntryRecord> r = record.empty() ? std::nullopt : readMadeEntryRecord(record);
  if (!r || r->identity != entryIdentity(entry)) return false;
  if (r->made.empty()) return descriptor < 0 && bornJustAfter(entry, record);
  if (r->made != madeIdentity(entry, descriptor)) return false;
  // Without a birth time ("-") the inode alone names the entry, and a file a user makes there later may be given the
  // same one: then only the stamp of occsweep's last write tells them apart.
  // A stamp an occsweep before status-change times wrote proves what it proved then.
  const bool has_change_time = r->written.find(" changed ") != std::string::npos;
  return !r->made.ends_with(" -") ||
         (!r->written.empty() &&
          r->written == (has_change_time ? writtenStamp(entry, descriptor) : contentStamp(entry, descriptor)));
}

bool keepsBirthTime(const fs::path& entry) {
  const std::string stamp = entryStamp(entry);
  return !stamp.empty() && !stamp.ends_with(" -");
}

void forgetMadeEntry(const fs::path& entry) {
  const fs::path record = madeEntryRecord(entry);
  std::error_code ec;
  if (!record.empty()) fs::remove(record, ec);
}

}  // namespace occsweep
