// Where an output may be written, and what it may replace (docs/io.md, "Outputs and --force").
#include "occsweep/io/output_target.hpp"
#include "occsweep/io/bounded_read.hpp"
#include "occsweep/io/json_prefix.hpp"
#include "occsweep/io/ownership.hpp"
#include "output_registry.hpp"

#include <algorithm>
#include <cstring>
#include <sys/stat.h>

namespace occsweep {
namespace fs = std::filesystem;
using namespace io_detail;

namespace {

bool isEmptyFolder(const fs::path& p) {
  std::error_code ec;
  return fs::is_directory(fs::symlink_status(p, ec)) && fs::is_empty(p, ec);
}

}  // namespace

TargetState io_detail::stateOf(const fs::path& p) {
  struct stat st {};
  if (::lstat(p.c_str(), &st) != 0) return {};
  return {true, isEmptyFolder(p), st.st_dev, st.st_ino, st.st_size, st.st_mtim, {}};
}

bool io_detail::sameEntry(const TargetState& a, const TargetState& b) {
  return a.device == b.device && a.inode == b.inode && a.size == b.size && a.modified.tv_sec == b.modified.tv_sec &&
         a.modified.tv_nsec == b.modified.tv_nsec;
}

fs::path io_detail::targetKey(const fs::path& target) {
  std::error_code ec;
  const fs::path key = fs::weakly_canonical(fs::absolute(target, ec), ec);
  return ec ? fs::absolute(target, ec) : key;
}

std::map<fs::path, TargetState>& io_detail::checkedTargets() {
  static auto* targets = new std::map<fs::path, TargetState>;
  return *targets;
}

// A target no checkOutputTarget accepted is replaced by nothing: whatever stands there at the commit (a user's file
// written while occsweep ran, or before it) stays, and the commit fails naming it (docs/io.md, "Ownership").
TargetState io_detail::checkedState(const fs::path& target) {
  std::lock_guard lock(registryMutex());
  const auto it = checkedTargets().find(targetKey(target));
  return it != checkedTargets().end() ? it->second : TargetState{};
}



ReplaceableOutput textOutput(const std::string& name, const std::string& first_line) {
  return {name, [first_line](const fs::path& file) {
            return notOwnReservedFile(file, first_line).empty() && holdsMarkedBytes(file);
          }};
}

std::vector<fs::path> missingFolders(const fs::path& dir) {
  std::vector<fs::path> missing;
  std::error_code ec;
  for (fs::path p = dir; !p.empty() && !fs::exists(fs::symlink_status(p, ec)); p = p.parent_path()) {
    missing.push_back(p);
    if (p == p.parent_path()) break;
  }
  return missing;
}

void removeEmptyFolders(const std::vector<fs::path>& folders) noexcept {
  std::error_code ec;
  for (const fs::path& p : folders) fs::remove(p, ec);  // refuses a folder that is not empty
}

ReplaceableOutput jsonOutput(const std::string& name, const std::string& format) {
  return {name, [format](const fs::path& file) {
            std::error_code ec;
            if (!fs::is_regular_file(fs::symlink_status(file, ec))) return false;
            return jsonFormatField(file) == format;  // its first bytes: a file of gigabytes is never read whole
          }};
}

namespace {

// An output as the writer reads it, and as the system resolves it ("link/.." is the link target's parent).
struct OutputReadings {
  fs::path lexical, resolved;
};

OutputReadings outputReadings(const fs::path& output) {
  auto dropTrailingSlash = [](fs::path p) { return p.has_filename() ? p : p.parent_path(); };
  const fs::path lexical = dropTrailingSlash(fs::absolute(output).lexically_normal());
  std::error_code ec;
  const fs::path resolved = dropTrailingSlash(fs::weakly_canonical(fs::absolute(output), ec));
  return {lexical, ec ? lexical : resolved};
}

// An output whose ".." follows a symbolic link reads two ways: the writer's (lexical: "link/.." is the link's own
// folder) and the system's ("link/.." is the link target's parent). Every check and the write must mean one file,
// so such a path is refused (docs/io.md, "Ownership").
void requireOneReading(const fs::path& output) {
  const OutputReadings r = outputReadings(output);
  std::error_code ec;
  const fs::path lexical_resolved = fs::weakly_canonical(r.lexical, ec);
  if (ec || lexical_resolved == r.resolved) return;
  throw OutputError(output.string() + ": '..' after a symbolic link names " + r.resolved.string() +
                    " to the system but " + lexical_resolved.string() +
                    " read as written: give the path without '..' (nothing was changed)");
}

// `inner` is `outer` or lies under it.
bool within(const fs::path& inner, const fs::path& outer) {
  return std::mismatch(outer.begin(), outer.end(), inner.begin(), inner.end()).first == outer.end();
}

// The existing entry that blocks the path to `output`: a file or a broken link where a folder must be (the writer
// makes missing folders, but none under a file or through a broken link); empty when none does.
fs::path blockingEntry(const fs::path& output) {
  std::error_code ec;
  for (fs::path p = outputReadings(output).lexical.parent_path(); !p.empty(); p = p.parent_path()) {
    if (fs::symlink_status(p, ec).type() != fs::file_type::not_found) return fs::is_directory(p, ec) ? fs::path() : p;
    if (p == p.parent_path()) break;
  }
  return {};
}

}  // namespace

void requireCompanionName(const fs::path& target, const std::string& suffix) {
  const std::string name = outputTarget(target).filename().string();
  if (name.size() + suffix.size() <= kFileNameMax) return;
  throw OutputError(target.string() + ": a name of " + std::to_string(name.size()) + " bytes leaves no room for its " +
                    "companion NAME" + suffix + " (a file name has at most 255 bytes): choose a name of at most " +
                    std::to_string(kFileNameMax - suffix.size()) + " bytes");
}

namespace {
// One name in one existing folder, by the folder's identity (device and inode): two spellings of a folder that no
// path comparison sees as one (a bind mount) still name one file.
bool sameNameInSameFolder(const OutputReadings& a, const OutputReadings& b) {
  if (a.resolved.filename() != b.resolved.filename()) return false;
  struct stat fa {}, fb {};
  if (::stat(a.resolved.parent_path().c_str(), &fa) != 0 || ::stat(b.resolved.parent_path().c_str(), &fb) != 0)
    return false;
  return fa.st_dev == fb.st_dev && fa.st_ino == fb.st_ino;
}
}  // namespace

bool outputsCollide(const fs::path& a, const fs::path& b) {
  const OutputReadings ra = outputReadings(a), rb = outputReadings(b);
  for (const auto& [x, y] : {std::pair{ra.lexical, rb.lexical}, {ra.resolved, rb.resolved}})
    if (within(x, y) || within(y, x)) return true;
  return sameNameInSameFolder(ra, rb);
}

void requireSeparateOutputs(const std::vector<std::pair<std::string, fs::path>>& outputs) {
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    const auto& [flag, path] = outputs[i];
    if (path.empty()) continue;
    requireOneReading(path);
    if (const fs::path entry = blockingEntry(path); !entry.empty())
      throw OutputError(flag + " " + path.string() + ": " + entry.string() + " is not a folder");
    for (std::size_t j = i + 1; j < outputs.size(); ++j)
      if (!outputs[j].second.empty() && outputsCollide(path, outputs[j].second))
        throw OutputError(flag + " and " + outputs[j].first + " name one file, or one lies under the other (" +
                          path.string() + ", " + outputs[j].second.string() + "): each output needs a file of its own");
  }
}

void checkOutputTarget(const fs::path& target, bool force, const ReplaceableOutput& kind) {
  requireOneReading(target);
  const fs::path t = outputTarget(target);
  std::error_code ec;
  const fs::path here = fs::weakly_canonical(fs::current_path(), ec), there = fs::weakly_canonical(t, ec);
  const auto [mismatch, _] = std::mismatch(there.begin(), there.end(), here.begin(), here.end());
  if (!there.empty() && mismatch == there.end())
    throw OutputError(target.string() + ": is the current folder or holds it: choose a new folder for the " +
                      kind.name);
  // A link is the user's entry whatever it points to: replacing it would drop their link, writing through it would
  // write elsewhere (docs/io.md, "Ownership").
  if (fs::is_symlink(fs::symlink_status(t, ec)))
    throw OutputError(target.string() + ": is a symbolic link: occsweep never writes through or replaces one, even "
                      "with --force (nothing was changed); give the path it points to, or choose another path");
  // A FIFO, socket or device is no one's output, and reading it for occsweep's mark would wait for ever on a FIFO:
  // refused at once, named by what it is (docs/robustness.md, "Limits and non-regular files").
  if (fs::is_other(fs::symlink_status(t, ec))) requireRegularFile(t);
  TargetState state = stateOf(t);
  if (state.exists && !state.empty_folder) {
    if (!force)
      throw OutputError(target.string() + ": exists: occsweep replaces nothing unless asked (--force replaces " +
                        "occsweep's own previous " + kind.name + "; or choose another path)");
    // A second name (a hard link) is the user's hold on these bytes, as a symbolic link is ("Ownership").
    if (struct stat st {}; ::lstat(t.c_str(), &st) == 0 && S_ISREG(st.st_mode) && st.st_nlink != 1)
      throw OutputError(target.string() + ": has " + std::to_string(st.st_nlink) + " names (a hard link): occsweep " +
                        "never replaces a file another name shares, even with --force (nothing was changed); remove " +
                        "the other name, or choose another path");
    if (!kind.is_own(t))
      throw OutputError(target.string() + ": exists and is not occsweep's " + kind.name +
                        ": refused even with --force (nothing was changed)");
    state.is_own = kind.is_own;
  }
  std::lock_guard lock(registryMutex());
  checkedTargets()[targetKey(t)] = state;  // the state a commit may replace (placeOutput)
}

}  // namespace occsweep
