// Temporary names, and what a killed run left beside an output (docs/io.md, "Ownership").
#include "occsweep/io/ownership.hpp"
#include "occsweep/io/output_target.hpp"
#include "occsweep/io/control_characters.hpp"
#include "occsweep/io/fnv1a.hpp"
#include "occsweep/io/process_stat.hpp"

#include <algorithm>
#include <cstring>
#include <fcntl.h>
#include <iostream>
#include <mutex>
#include <random>
#include <set>
#include <sys/stat.h>
#include <sys/xattr.h>
#include <unistd.h>
#include <vector>

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

// The part of an output's name its temporaries carry: the whole name, or as much of it as keeps the temporary
// within the file system's 255 bytes (NAME_MAX) beside a 9-digit PID and the token, so that a legal 255-byte
// output name still has a legal temporary.
std::string temporaryStem(const std::string& output_name) {
  constexpr std::size_t kRest = 1 + 5 + 9 + 1 + kTokenDigits;  // "." ".tmp-" PID "-" TOKEN
  return output_name.size() + kRest <= kFileNameMax ? output_name : output_name.substr(0, kFileNameMax - kRest);
}

// The PID of `.NAME.tmp-PID-TOKEN` for output `output_name`; -1 when `component` is not named so.
long temporaryPid(const std::string& component, const std::string& output_name) {
  std::string prefix = ".";  // piece by piece: "." + std::string trips GCC 12's -Wrestrict false positive
  prefix += temporaryStem(output_name);
  prefix += kTemporaryMark;
  if (!component.starts_with(prefix)) return -1;
  const std::string rest = component.substr(prefix.size());
  const std::size_t dash = rest.find('-');
  if (dash == std::string::npos || dash == 0 || dash > 9 || rest.size() - dash - 1 != kTokenDigits) return -1;
  if (rest.find_first_not_of("0123456789") < dash) return -1;
  if (rest.find_first_not_of("0123456789abcdef", dash + 1) != std::string::npos) return -1;
  return std::stol(rest.substr(0, dash));
}

}  // namespace

fs::path temporaryNameFor(const fs::path& target) {
  std::string name = ".";
  name += temporaryStem(target.filename().string());
  name += kTemporaryMark + std::to_string(::getpid()) + "-" + randomToken();
  return target.parent_path() / name;
}

std::string outputNameOf(const std::string& component) {
  const std::size_t mark = component.rfind(kTemporaryMark);
  if (component.size() < 2 || component[0] != '.' || mark == std::string::npos || mark < 2) return component;
  const std::string name = component.substr(1, mark - 1);
  return temporaryPid(component, name) > 0 ? name : component;
}

bool isLeftoverTemporaryOf(const fs::path& entry, const fs::path& target) {
  const long pid = temporaryPid(entry.filename().string(), target.filename().string());
  if (pid <= 0 || pid == ::getpid()) return false;
  const std::optional<ProcessStat> stat = processStat(pid);
  return !stat || stat->state == 'Z';
}

void reportLeftoverTemporaries(const fs::path& target) {
  static std::mutex mutex;
  static std::set<fs::path> reported;  // once per target: a sweep opens many temporaries beside one output
  const std::lock_guard lock(mutex);
  if (!reported.insert(target).second) return;
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::error_code ec;
  std::vector<fs::path> leftovers;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
    if (isLeftoverTemporaryOf(it->path(), target)) leftovers.push_back(it->path());
  for (const fs::path& p : leftovers) {
    std::string command = "rm -r -- " + shownShellWord(p.string());
    const fs::path journal = p.string() + "-journal";  // what a kill of a store being written there leaves
    if (fs::exists(fs::symlink_status(journal, ec))) command += " " + shownShellWord(journal.string());
    std::cerr << "occsweep: warning: " << escapedControlCharacters(p.string()) << " is named as a temporary of "
              << escapedControlCharacters(target.string()) << " whose process does not run on this machine (a "
              << "killed occsweep's, unless another machine's occsweep writes this folder); occsweep never removes "
              << "it. Once it is not in use, remove it:\n  " << command << '\n';
  }
}

namespace {

// Why the file open at `fd` is not a regular file with one name ("" when it is), and its first `max_bytes` in `head`.
std::string readOpenFile(int fd, std::size_t max_bytes, std::string& head) {
  head.clear();
  struct stat st {};
  if (::fstat(fd, &st) != 0) return "cannot be read";
  if (!S_ISREG(st.st_mode)) return "is not a regular file";
  if (st.st_nlink != 1) return "has " + std::to_string(st.st_nlink) + " names (a hard link shares its bytes)";
  head.resize(std::min<std::size_t>(max_bytes, std::size_t(st.st_size)));
  // A short read would make a file look empty or unmarked: what cannot be read whole is no one's to take.
  if (::pread(fd, head.data(), head.size(), 0) != ssize_t(head.size())) return "cannot be read";
  return "";
}

std::string whyNotMarked(const std::string& head, const std::string& mark, bool empty_is_own) {
  if (empty_is_own && head.empty()) return "";
  return head == mark ? "" : "does not start with occsweep's line \"" + mark + "\"";
}

}  // namespace

std::string readReservedFile(const fs::path& file, std::size_t max_bytes, std::string& head) {
  head.clear();
  struct stat named {}, opened {};
  if (::lstat(file.c_str(), &named) != 0) return "cannot be read";
  if (S_ISLNK(named.st_mode)) return "is a symbolic link";
  if (!S_ISREG(named.st_mode)) return "is not a regular file";
  // Opened without following a link or waiting on a FIFO, and read only if it is still the file looked at.
  const int fd = ::open(file.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return "cannot be read";
  const bool same = ::fstat(fd, &opened) == 0 && opened.st_dev == named.st_dev && opened.st_ino == named.st_ino;
  std::string why = same ? readOpenFile(fd, max_bytes, head) : "was replaced while occsweep read it";
  ::close(fd);
  return why;
}

std::string notOwnReservedFile(const fs::path& file, const std::string& mark, bool empty_is_own) {
  std::string head;
  if (std::string why = readReservedFile(file, mark.size(), head); !why.empty()) return why;
  return whyNotMarked(head, mark, empty_is_own);
}

std::string notOwnOpenFile(int fd, const std::string& mark, bool empty_is_own) {
  std::string head;
  if (std::string why = readOpenFile(fd, mark.size(), head); !why.empty()) return why;
  return whyNotMarked(head, mark, empty_is_own);
}

namespace {
constexpr const char* kMarkAttribute = "user.occsweep.fnv1a";

std::string hashOfFile(const fs::path& file) {
  Fnv1a h;
  h.feedFile(file);
  return h.hex();
}
}  // namespace

void markWrittenBytes(const fs::path& file) {
  const std::string hash = hashOfFile(file);
  if (::lsetxattr(file.c_str(), kMarkAttribute, hash.data(), hash.size(), 0) == 0) return;
  const fs::path shown = file.parent_path() / outputNameOf(file.filename().string());
  std::cerr << "occsweep: warning: " << escapedControlCharacters(shown.string()) << ": cannot mark it as occsweep's ("
            << std::strerror(errno) << ": a file system without user attributes): a later --force will not "
            << "replace it; remove it first to write it again (docs/io.md, \"Ownership\")\n";
}

bool holdsMarkedBytes(const fs::path& file) {
  char mark[32] = {};
  const ssize_t n = ::lgetxattr(file.c_str(), kMarkAttribute, mark, sizeof mark);
  if (n <= 0) return false;
  try {
    return std::string(mark, std::size_t(n)) == hashOfFile(file);
  } catch (const std::exception&) {
    return false;
  }
}

bool removeTemporaryEntry(const fs::path& path) noexcept {
  std::error_code ec;
  // occsweep never makes a temporary (or journal) that is a symbolic link: one there is the user's, and stays.
  if (fs::is_symlink(fs::symlink_status(path, ec))) return false;
  // Another thread of this run may still be making a file in a temporary folder (an interrupt's cleaner runs beside
  // the writer): removed again until the folder itself is gone, which ends such a writer's creations.
  for (int attempt = 0; attempt < 100; ++attempt) {
    ec.clear();
    fs::remove_all(path, ec);
    std::error_code gone;
    if (!fs::exists(fs::symlink_status(path, gone))) break;
  }
  const fs::path journal = path.string() + "-journal";  // what a kill of a store being written there leaves
  std::error_code journal_ec;
  if (!fs::is_symlink(fs::symlink_status(journal, journal_ec))) fs::remove(journal, journal_ec);
  return !ec;
}

fs::path outputPathOf(const fs::path& file) {
  fs::path shown;
  for (const auto& part : file) shown /= outputNameOf(part.string());
  return shown;
}

std::string writeFailure(const fs::path& file, int error_number) {
  const std::string name = outputPathOf(file).string();
  switch (error_number) {
    case ENOSPC: return name + ": no space left on device";
    case EDQUOT: return name + ": disk quota exceeded";
    case EFBIG: return name + ": file size limit exceeded (ulimit -f)";
    default: return name + ": cannot write: " + std::strerror(error_number);
  }
}

fs::path outputTarget(const fs::path& target) {
  fs::path p = target.lexically_normal();
  if (!p.has_filename() && p.has_parent_path()) p = p.parent_path();  // "s1/" is "s1"
  const std::string name = p.filename().string();
  if (p.empty() || name == "." || name == ".." || p.begin()->string() == "..") {
    p = (fs::current_path() / target).lexically_normal();
    if (!p.has_filename() && p != p.root_path()) p = p.parent_path();
  }
  return p;
}

}  // namespace occsweep
