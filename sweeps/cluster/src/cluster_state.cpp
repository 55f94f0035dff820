// Task status from outputs on disk and Slurm's records, and which tasks a resubmission must run.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstring>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <set>

#include <nlohmann/json.hpp>

#include "occsweep/io/bounded_read.hpp"
#include "occsweep/io/ownership.hpp"
#include "occsweep/io/process_stat.hpp"
#include "occsweep/sweeps/cluster_state.hpp"
#include "occsweep/sweeps/merge.hpp"
#include "occsweep/sweeps/results_diff.hpp"
#include "occsweep/eval/json_input.hpp"

namespace occsweep {
namespace fs = std::filesystem;

fs::path runningMarker(const fs::path& dir, const std::string& stage, std::uint64_t task) {
  return dir / "running" / (stage + "-" + std::to_string(task) + ".pid");
}

namespace {
/// A running marker's first line: what marks it run-local's; the task's pid follows on the second.
constexpr const char* kMarkerMark = "# occsweep cluster run-local: running task";
}  // namespace

std::string foreignMarkerMessage(const fs::path& marker) {
  std::string why = notOwnReservedFile(marker, kMarkerMark);
  if (why.empty()) why = "is the marker of a task still running";
  return marker.string() + ": " + why + ", where run-local keeps a running task's marker: occsweep never removes "
         "it; once no task of the plan runs, move it away";
}

RunningMarker createRunningMarker(const fs::path& dir, const std::string& stage, std::uint64_t task) {
  RunningMarker m{runningMarker(dir, stage, task)};
  const int fd = ::open(m.path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
  struct stat made {};
  const std::string mark = std::string(kMarkerMark) + "\n";
  if (fd < 0 || ::fstat(fd, &made) != 0 || ::write(fd, mark.data(), mark.size()) != ssize_t(mark.size())) {
    const int e = errno;
    if (fd >= 0) ::close(fd);
    throw std::runtime_error(e == EEXIST ? foreignMarkerMessage(m.path) : m.path.string() + ": " + std::strerror(e));
  }
  ::close(fd);
  m.device = made.st_dev, m.inode = made.st_ino;
  return m;
}

void writeRunningMarker(const RunningMarker& marker, pid_t pid) {
  const int fd = ::open(marker.path.c_str(), O_WRONLY | O_APPEND | O_NOFOLLOW | O_CLOEXEC);
  struct stat now {};
  if (fd < 0) return;  // removed meanwhile: the task runs without one, as one killed before it was written
  const std::string text = std::to_string(pid) + "\n";
  const bool same = ::fstat(fd, &now) == 0 && now.st_dev == marker.device && now.st_ino == marker.inode;
  if (same) (void)!::write(fd, text.data(), text.size());  // a marker without its pid only hides a live task
  ::close(fd);
}

void removeRunningMarker(const RunningMarker& marker) {
  struct stat now {};
  if (::lstat(marker.path.c_str(), &now) != 0 || now.st_dev != marker.device || now.st_ino != marker.inode) return;
  std::error_code ec;
  fs::remove(marker.path, ec);
}

void removeStaleMarkers(const fs::path& dir) {
  std::error_code ec;
  std::vector<fs::path> markers;
  for (fs::directory_iterator it(dir / "running", ec), end; !ec && it != end; it.increment(ec))
    if (it->path().extension() == ".pid" && notOwnReservedFile(it->path(), kMarkerMark).empty())
      markers.push_back(it->path());
  for (const auto& m : markers) fs::remove(m, ec);
}

pid_t liveLocalTask(const fs::path& dir, const std::string& stage, std::uint64_t task) {
  // Never read through a link, and never a FIFO, which would block status and run-local: a marker is a regular file.
  const fs::path marker = runningMarker(dir, stage, task);
  std::error_code ec;
  std::string text;  // the mark's line, then the pid's
  if (!readReservedFile(marker, 128, text).empty() || !text.starts_with(kMarkerMark)) return 0;
  long pid = 0;
  if (!(std::istringstream(text.substr(std::min(text.size(), text.find('\n') + 1))) >> pid) || pid <= 0) return 0;
  // Alive and not a zombie.
  const std::optional<ProcessStat> stat = processStat(pid);
  if (!stat || stat->state == 'Z') return 0;
  // A pid reused by an unrelated process after a reboot or a long time: the task runs in the plan folder.
  const auto cwd = fs::read_symlink("/proc/" + std::to_string(pid) + "/cwd", ec);
  if (ec || !fs::equivalent(cwd, dir, ec)) return 0;
  return pid_t(pid);
}

namespace {
/// The first header field where a results file describes other work than the task's plan fixes (its Eq. 16 group,
/// map settings, truth), as "FIELD VALUE, expected VALUE"; empty when it matches or the plan fixes none.
std::string otherWork(const ResultsHeader& found, const ClusterTask& task) {
  if (!task.expect_work) return "";
  const ExpectedWork& w = *task.expect_work;
  ResultsHeader expected = found;
  expected.selection.group = w.group;
  expected.map = w.map;
  expected.truth = w.truth;
  const auto fields = incomparableHeaderFields(expected, found, false);
  if (fields.empty()) return "";
  const ResultsDifference& d = fields.front();
  return d.field + " " + d.candidate + ", expected " + d.golden;
}
}  // namespace

std::string checkOutput(const ClusterTask& task, const fs::path& dir) {
  const fs::path file = dir / task.output;
  std::error_code ec;
  if (!fs::exists(file, ec)) return "missing";
  try {
    switch (task.kind) {
      case OutputKind::Exists:
        return "";
      case OutputKind::Dataset: {  // readJsonFile refuses a FIFO, which would block `cluster status`
        if (!fs::exists(file / "manifest.json")) return "no manifest.json";
        return readJsonFile(file / "manifest.json").is_object() ? "" : "manifest.json is not an object";
      }
      case OutputKind::Comparison: {
        const auto j = readJsonFile(file);
        if (!j.is_object() || j.value("format", "") != "occsweep-comparison" || !j.contains("rows") ||
            !j["rows"].is_array())
          return "not an occsweep-comparison file";
        return "";
      }
      case OutputKind::Results: {
        const ResultsFile f = readResults(file);
        if (!f.complete) return "incomplete results";
        if (f.header.grid_name != task.expect_grid)
          return "grid " + f.header.grid_name + ", expected " + task.expect_grid;
        const auto& s = f.header.selection;
        if (s.shard_index != task.expect_shard || s.shard_count != task.expect_shards)
          return "shard " + std::to_string(s.shard_index) + "/" + std::to_string(s.shard_count) + ", expected " +
                 std::to_string(task.expect_shard) + "/" + std::to_string(task.expect_shards);
        if (const std::string why = otherWork(f.header, task); !why.empty()) return why;
        (void)checkAgainstGrid(f, file.string());
        return "";
      }
    }
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

namespace {
bool insideFolder(const fs::path& file, const fs::path& dir) {
  std::error_code ec;
  const fs::path f = fs::weakly_canonical(file, ec);
  if (ec) return false;
  const fs::path d = fs::weakly_canonical(dir, ec);
  if (ec) return false;
  const fs::path rel = f.lexically_relative(d);
  return !rel.empty() && *rel.begin() != ".." && *rel.begin() != ".";
}
}  // namespace

void requireOutputInside(const ClusterTask& task, const fs::path& dir) {
  if (!insideFolder(dir / task.output, dir))
    throw std::runtime_error((dir / task.output).string() + ": task " + std::to_string(task.index) +
                             "'s output leads out of the plan folder (through a symbolic link on its way): a task "
                             "writes only inside its plan folder (docs/cluster.md); remove the link");
}

void removeOwnOutput(const ClusterTask& task, const fs::path& dir) {
  const fs::path file = dir / task.output;
  std::error_code ec;
  // An `exists` output has no check that proves it occsweep's (its name alone proves nothing): it stays, and the
  // task's own command decides by its --force rule (docs/cluster.md, "Outputs stay in the plan folder").
  if (task.kind == OutputKind::Exists) return;
  // A symbolic link is the user's entry whatever it points to (docs/io.md, "Ownership").
  if (!fs::is_regular_file(fs::symlink_status(file, ec)) || !insideFolder(file, dir) || !checkOutput(task, dir).empty())
    return;
  fs::remove(file, ec);
}

bool outputStale(const ClusterTask& task, const fs::path& dir) {
  std::error_code ec;
  const auto out_time = fs::last_write_time(dir / task.output, ec);
  if (ec) return false;
  for (const auto& in : task.inputs) {
    const auto t = fs::last_write_time(dir / in, ec);
    if (!ec && t > out_time) return true;
  }
  return false;
}

namespace {

/// One whole line appended to a plan file, never through a symbolic link at its name (docs/io.md,
/// "Ownership"), and only to a regular file: O_NONBLOCK, so that a FIFO there is refused, never waited on; O_APPEND:
/// one write, one line.
void appendLine(const fs::path& file, const std::string& line) {
  const int fd = ::open(file.c_str(), O_WRONLY | O_APPEND | O_CREAT | O_CLOEXEC | O_NOFOLLOW | O_NONBLOCK, 0644);
  const int error = fd < 0 ? errno : 0;  // ENXIO: a FIFO that no process reads
  struct stat opened {};
  const bool regular = fd >= 0 && ::fstat(fd, &opened) == 0 && S_ISREG(opened.st_mode);
  const bool written = regular && ::write(fd, line.data(), line.size()) == ssize_t(line.size());
  if (fd >= 0) ::close(fd);
  if (error == ELOOP)
    throw std::runtime_error(file.string() + ": is a symbolic link: occsweep never writes through one; remove it");
  if (error != 0 && error != ENXIO) throw std::runtime_error(file.string() + ": cannot open: " + std::strerror(error));
  if (!regular)
    throw std::runtime_error(file.string() + ": is not a regular file: occsweep appends only to one; move it away");
  if (!written) throw std::runtime_error(file.string() + ": cannot append");
}

/// Each line of the plan file `name` in DIR (none: nothing), parsed as JSON and handed to `read`; a line it refuses
/// (or that is not JSON) is refused naming the file, the line and `what` it should be. Read whole as a bounded
/// regular file: a FIFO or a device is refused, not read.
template <class Read>
void readJsonLines(const fs::path& dir, const std::string& name, const std::string& what, Read read) {
  const fs::path path = dir / name;
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(path, ec))) return;
  std::istringstream in(readFileBytes(path, std::uint64_t(1) << 30));
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    if (line.empty()) continue;
    try {
      read(nlohmann::json::parse(line));
    } catch (const std::exception& e) {
      throw std::runtime_error(path.string() + ":" + std::to_string(n) + ": not " + what + ": " + e.what());
    }
  }
}

}  // namespace

std::vector<Submission> readSubmissions(const fs::path& dir) {
  std::vector<Submission> out;
  readJsonLines(dir, "submissions.jsonl", "a submission record", [&](const nlohmann::json& j) {
    out.push_back({j.at("stage").get<std::string>(), j.at("job_id").get<std::string>(),
                   j.at("tasks").get<std::vector<std::uint64_t>>(), j.value("offset", std::uint64_t(0))});
    for (const std::uint64_t t : out.back().tasks)
      if (t < out.back().offset) throw std::runtime_error("task " + std::to_string(t) + " is below the offset");
  });
  return out;
}

void appendSubmission(const fs::path& dir, const Submission& s) {
  appendLine(dir / "submissions.jsonl",
             nlohmann::json{{"stage", s.stage}, {"job_id", s.job_id}, {"tasks", s.tasks}, {"offset", s.offset}}.dump() +
                 '\n');
}

void appendMeasurement(const fs::path& dir, const TaskMeasurement& m) {
  appendLine(dir / "measured.jsonl", nlohmann::json{{"stage", m.stage},
                                                    {"task", m.task},
                                                    {"label", m.label},
                                                    {"argv", m.argv},
                                                    {"wall_seconds", m.wall_seconds},
                                                    {"cpu_seconds", m.cpu_seconds},
                                                    {"peak_bytes", m.peak_bytes},
                                                    {"exit_code", m.exit_code},
                                                    {"succeeded", m.succeeded}}
                                         .dump() +
                                         '\n');
}

std::vector<TaskMeasurement> readMeasurements(const fs::path& dir) {
  std::vector<TaskMeasurement> out;
  readJsonLines(dir, "measured.jsonl", "a task measurement", [&](const nlohmann::json& j) {
    TaskMeasurement m{j.at("stage").get<std::string>(), j.at("task").get<std::uint64_t>(),
                      j.at("label").get<std::string>(), j.at("argv").get<std::vector<std::string>>(),
                      j.at("wall_seconds").get<double>(), j.at("cpu_seconds").get<double>(),
                      j.at("peak_bytes").get<std::uint64_t>(), j.at("exit_code").get<int>(),
                      j.at("succeeded").get<bool>()};
    for (const double seconds : {m.wall_seconds, m.cpu_seconds})
      if (!std::isfinite(seconds) || seconds < 0 || seconds > 1e9)
        throw std::invalid_argument("a time outside 0 to 10^9 s");
    if (!j.at("peak_bytes").is_number_unsigned() || m.peak_bytes >= (std::uint64_t(1) << 50))
      throw std::invalid_argument("peak_bytes outside 0 to 2^50");
    out.push_back(std::move(m));
  });
  return out;
}

LastSuccesses::LastSuccesses(const std::vector<TaskMeasurement>& measurements) {
  for (const TaskMeasurement& m : measurements)
    if (m.succeeded) last_[{m.stage, m.task}] = &m;
}

const TaskMeasurement* LastSuccesses::of(const std::string& stage, const ClusterTask& task) const {
  const auto it = last_.find({stage, task.index});
  return it == last_.end() || it->second->argv != task.argv ? nullptr : it->second;  // another command at that index
}

std::vector<MeasuredStage> measuredStages(const ClusterPlan& plan, const std::vector<TaskMeasurement>& measurements) {
  const LastSuccesses last(measurements);
  std::vector<MeasuredStage> out;
  for (const ClusterStage& stage : plan.stages) {
    MeasuredStage& row = out.emplace_back();
    row.stage = stage.name;
    row.tasks = stage.tasks.size();
    for (const ClusterTask& task : stage.tasks) {
      const TaskMeasurement* measured = last.of(stage.name, task);
      if (!measured) continue;
      const TaskMeasurement& m = *measured;
      ++row.measured;
      row.wall_seconds += m.wall_seconds;
      row.longest_seconds = std::max(row.longest_seconds, m.wall_seconds);
      row.cpu_seconds += m.cpu_seconds;
      row.peak_bytes = std::max(row.peak_bytes, m.peak_bytes);
    }
  }
  return out;
}

const char* stateName(TaskState s) {
  switch (s) {
    case TaskState::Done: return "done";
    case TaskState::Running: return "running";
    case TaskState::Pending: return "pending";
    case TaskState::Failed: return "failed";
    case TaskState::Stale: return "stale";
    case TaskState::Invalid: return "invalid";
    case TaskState::Missing: return "missing";
  }
  return "missing";
}

std::vector<std::vector<TaskStatus>> planStatus(const ClusterPlan& plan, const fs::path& dir,
                                                const std::map<std::string, SlurmRecord>& records,
                                                const std::vector<Submission>& submissions) {
  std::map<std::pair<std::string, std::uint64_t>, std::string> latest;  // (stage, task) -> JOBID_TASK
  for (const auto& s : submissions)
    for (auto t : s.tasks) latest[{s.stage, t}] = s.job_id + "_" + std::to_string(t - s.offset);
  static const std::set<std::string> pending = {"PENDING", "REQUEUED", "REQUEUE_HOLD", "REQUEUE_FED", "SUSPENDED"};
  static const std::set<std::string> running = {"RUNNING", "CONFIGURING", "COMPLETING", "RESIZING", "STAGE_OUT",
                                                "SIGNALING"};
  std::vector<std::vector<TaskStatus>> out;
  for (const auto& stage : plan.stages) {
    auto& row = out.emplace_back();
    for (const auto& task : stage.tasks) {
      TaskStatus st;
      const auto id = latest.find({stage.name, task.index});
      const SlurmRecord* rec = nullptr;
      if (id != latest.end()) {
        st.slurm_id = id->second;
        const auto r = records.find(id->second);
        if (r != records.end()) rec = &r->second;
      }
      if (rec && (pending.count(rec->state) || running.count(rec->state))) {
        st.state = pending.count(rec->state) ? TaskState::Pending : TaskState::Running;
        st.detail = rec->reason;
      } else if (const pid_t pid = liveLocalTask(dir, stage.name, task.index); pid > 0) {
        st.state = TaskState::Running;
        st.detail = "run-local pid " + std::to_string(pid);
      } else if (const std::string why = checkOutput(task, dir); why.empty()) {
        st.state = outputStale(task, dir) ? TaskState::Stale : TaskState::Done;
        if (st.state == TaskState::Stale) st.detail = "older than an input";
      } else if (rec) {
        st.state = TaskState::Failed;
        st.detail = rec->state == "COMPLETED" ? "slurm COMPLETED but output: " + why
                                              : "slurm " + rec->state + "; output: " + why;
      } else {
        std::error_code ec;
        st.state = fs::exists(dir / task.output, ec) ? TaskState::Invalid : TaskState::Missing;
        st.detail = why;
      }
      row.push_back(st);
    }
  }
  return out;
}

std::vector<std::vector<std::uint64_t>> tasksToRun(const ClusterPlan& plan,
                                                   const std::vector<std::vector<TaskStatus>>& status) {
  std::set<std::string> rewritten;  // outputs that this round writes again
  std::vector<std::vector<std::uint64_t>> out;
  for (std::size_t s = 0; s < plan.stages.size(); ++s) {
    auto& ids = out.emplace_back();
    for (const auto& task : plan.stages[s].tasks) {
      const TaskState st = status[s][task.index].state;
      if (st == TaskState::Running || st == TaskState::Pending) continue;
      bool run = st != TaskState::Done;
      for (const auto& in : task.inputs) run = run || rewritten.count(in);
      if (!run) continue;
      ids.push_back(task.index);
      rewritten.insert(task.output);
    }
  }
  return out;
}

std::string arrayRanges(const std::vector<std::uint64_t>& ids) {
  std::string out;
  for (std::size_t i = 0; i < ids.size();) {
    std::size_t j = i;
    while (j + 1 < ids.size() && ids[j + 1] == ids[j] + 1) ++j;
    if (!out.empty()) out += ',';
    out += std::to_string(ids[i]);
    if (j > i) (out += '-') += std::to_string(ids[j]);  // not "-" + ...: GCC 12 -Wrestrict false positive
    i = j + 1;
  }
  return out;
}

}  // namespace occsweep
