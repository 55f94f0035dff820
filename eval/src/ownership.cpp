// The ledger of temporaries (docs/robustness.md, "Ownership"): what proves a leftover temporary is occsweep's.
#include "occsweep/eval/ownership.hpp"
#include "occsweep/eval/fnv1a.hpp"
#include "occsweep/eval/process_stat.hpp"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <optional>
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

// The entry itself (not what a link there points to): its inode and birth time, as the fifth line of its record
// holds them. "" when it cannot be read.
std::string madeIdentity(const fs::path& path) {
  struct statx made {};
  if (::statx(AT_FDCWD, path.c_str(), AT_SYMLINK_NOFOLLOW, STATX_INO | STATX_BTIME, &made) != 0) return "";
  return "made " + std::to_string(made.stx_ino) + " " + birthText(made);
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
// fifth once it exists (recordTemporaryMade).
struct LedgerRecord {
  std::string process;
  fs::path path;
  std::string machine, entry, made;
};

std::optional<LedgerRecord> readRecord(const fs::path& ledger, const std::string& token) {
  std::ifstream in(ledger / token);
  LedgerRecord r;
  std::string path;
  if (!std::getline(in, r.process) || !std::getline(in, path) || !std::getline(in, r.machine)) return std::nullopt;
  std::getline(in, r.entry);  // "" in a record of an occsweep that kept no identity: it proves nothing
  std::getline(in, r.made);   // "" when a kill came between the making and its record, or from an older occsweep
  r.path = path;
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

bool unfinishedRecord(const fs::path& record) {
  std::error_code ec;
  const auto written = fs::last_write_time(record, ec);
  return !ec && fs::file_time_type::clock::now() - written > kUnfinishedRecordAge;
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
  out << processIdentity(::getpid()) << '\n' << canonicalEntry(c.path).string() << '\n' << machineLine(thisMachine())
      << '\n' << identity << '\n';
  out.flush();
  c.recorded = bool(out);
  return c;
}

void recordTemporaryMade(const TemporaryClaim& claim) {
  if (!claim.recorded) return;
  const std::string made = madeIdentity(claim.path);
  if (made.empty()) return;
  std::ofstream out(ownershipLedger() / claim.token, std::ios::app);
  out << made << '\n';
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

bool removeTemporaryEntry(const fs::path& path) noexcept {
  std::error_code ec, journal_ec;
  // occsweep never makes a temporary (or journal) that is a symbolic link: one there is the user's, and stays.
  if (fs::is_symlink(fs::symlink_status(path, ec))) return false;
  // A folder temporary is occsweep's as a whole: only occsweep wrote into it. Another thread of the same run may
  // still be making a file in it (an interrupt's cleaner runs beside the writer): removed again until the folder
  // itself is gone, which ends such a writer's creations (their folder no longer exists).
  for (int attempt = 0; attempt < 100; ++attempt) {
    ec.clear();
    fs::remove_all(path, ec);
    std::error_code gone;
    if (!fs::exists(fs::symlink_status(path, gone))) break;
  }
  const fs::path journal = path.string() + "-journal";
  if (!fs::is_symlink(fs::symlink_status(journal, journal_ec))) fs::remove(journal, journal_ec);
  return !ec;
}

bool removeStaleTemporary(const fs::path& entry, const fs::path& target) {
  const std::optional<std::string> token = staleRecord(entry, target);
  if (!token) return false;
  std::error_code ec;
  if (removeTemporaryEntry(entry)) fs::remove(ownershipLedger() / *token, ec);
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
  std::string identity, size, hash, path;
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
                          canonicalEntry(file).string()};
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
    const fs::path where = r->path.empty() ? fs::path(r->identity) : fs::path(r->path);  // a legacy record: its path
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

}  // namespace occsweep
