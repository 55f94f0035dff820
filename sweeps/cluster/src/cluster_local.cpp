// run-local: the same plan without Slurm, so a laptop and a cluster share one path.
#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstring>
#include <fcntl.h>
#include <fstream>
#include <iostream>
#include <map>
#include <string_view>
#include <memory>
#include <sys/file.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "occsweep/io/control_characters.hpp"
#include "occsweep/io/output_file.hpp"
#include "occsweep/io/ownership.hpp"
#include "occsweep/sweeps/cluster_slurm.hpp"
#include "occsweep/sweeps/progress.hpp"
#include "occsweep/io/temporaries.hpp"

namespace occsweep {
namespace fs = std::filesystem;

namespace {

/// run-local appends its measurements to DIR/measured.jsonl (docs/cluster.md, "Measured tasks") only where that file
/// is absent or one of its records: a regular file of this folder alone (one link: not a hard link to a file
/// elsewhere) whose every line reads as a task measurement. A symbolic link, a user's file, or one linked from
/// elsewhere is refused before any task starts, and left as it is.
void requireOwnMeasurements(const fs::path& dir) {
  const fs::path file = dir / "measured.jsonl";
  struct stat st{};
  if (::lstat(file.c_str(), &st) != 0) return;  // none yet: run-local makes it
  const auto refuse = [&](const std::string& why) {
    throw std::runtime_error(file.string() + ": " + why + ": run-local appends its measurements only to its own "
                             "file (docs/cluster.md, \"Measured tasks\"); move it away");
  };
  if (S_ISLNK(st.st_mode)) refuse("is a symbolic link");
  if (!S_ISREG(st.st_mode)) refuse("is not a regular file");
  if (st.st_nlink != 1) refuse("has " + std::to_string(st.st_nlink) + " hard links (another name shares its bytes)");
  try {
    (void)readMeasurements(dir);
  } catch (const std::exception& e) {
    refuse(std::string("holds a line that is not a task measurement (") + e.what() + ")");
  }
}

// ---- ending the tasks with run-local (docs/cluster.md, "Stopping run-local") ----
// The signal handler may only make async-signal-safe calls: it reads the pids of the running tasks from a fixed
// table of lock-free atomics, sends each SIGTERM and records the signal.
std::atomic<pid_t>* g_task_pids = nullptr;
std::size_t g_task_slots = 0;
volatile std::sig_atomic_t g_stop_signal = 0;
static_assert(std::atomic<pid_t>::is_always_lock_free);

void stopTasks(int signal) {
  g_stop_signal = signal;
  for (std::size_t i = 0; i < g_task_slots; ++i)
    if (const pid_t pid = g_task_pids[i].load(); pid > 0) ::kill(pid, SIGTERM);
}

/// SIGTERM, SIGINT and SIGHUP end the running tasks while alive; the old handlers come back after.
class TaskStopper {
 public:
  explicit TaskStopper(std::size_t slots) : pids_(new std::atomic<pid_t>[slots]) {
    for (std::size_t i = 0; i < slots; ++i) pids_[i] = 0;
    g_task_pids = pids_.get();
    g_task_slots = slots;
    g_stop_signal = 0;
    struct sigaction sa {};
    sa.sa_handler = stopTasks;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = 0;  // no SA_RESTART: waitpid returns EINTR, and the loop sees the signal
    for (std::size_t i = 0; i < 3; ++i) {  // an ignored signal (nohup's SIGHUP) stays ignored
      ::sigaction(kSignals[i], nullptr, &old_[i]);
      if (old_[i].sa_handler != SIG_IGN) ::sigaction(kSignals[i], &sa, nullptr);
    }
    // A signal that came before these handlers went to occsweep's interrupt cleaning, whose thread exits the process
    // when it is scheduled: start no task it would leave running (seen under load as a surviving task).
    if (const int earlier = interruptSignalReceived()) g_stop_signal = earlier;
  }
  TaskStopper(const TaskStopper&) = delete;
  TaskStopper& operator=(const TaskStopper&) = delete;
  ~TaskStopper() {
    for (std::size_t i = 0; i < 3; ++i) ::sigaction(kSignals[i], &old_[i], nullptr);
    g_task_slots = 0;
    g_task_pids = nullptr;
  }
  void track(std::size_t slot, pid_t pid) { pids_[slot] = pid; }
  void forget(std::size_t slot) { pids_[slot] = 0; }
  [[nodiscard]] int signal() const { return g_stop_signal; }
  /// Sends SIGTERM again from the main loop: a task started while the handler ran is not missed.
  void stopAll() const { stopTasks(g_stop_signal); }

 private:
  static constexpr int kSignals[3] = {SIGTERM, SIGINT, SIGHUP};
  std::unique_ptr<std::atomic<pid_t>[]> pids_;
  struct sigaction old_[3] {};
};

/// DIR/run-local.lock, held (flock) while this run-local runs: a second one on the same plan is refused. The
/// kernel releases it when the process dies, even by SIGKILL; the descriptor is not inherited by the tasks. Its
/// first line marks it run-local's, its second holds the pid.
class PlanLock {
 public:
  explicit PlanLock(const fs::path& dir) : file_(dir / "run-local.lock") {
    // O_NOFOLLOW: a symbolic link at the name is the user's, never opened (docs/io.md, "Ownership").
    fd_ = ::open(file_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW | O_NONBLOCK, 0644);
    if (fd_ < 0) {
      const int e = errno;
      if (e == ELOOP)
        throw std::runtime_error(file_.string() + ": is a symbolic link: occsweep never writes through one; remove it");
      throw std::runtime_error(file_.string() + ": cannot open: " + std::strerror(e));
    }
    // Empty is what a kill right after its creation leaves; anything else not marked (a user's file, a hard link
    // to one) is only locked, never written.
    const bool own = notOwnOpenFile(fd_, kMark, true).empty();
    if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
      const std::string holder = own ? holderPid() : "";
      ::close(fd_);
      throw std::runtime_error(dir.string() + ": another `cluster run-local` " +
                               (holder.empty() ? "" : "(pid " + holder + ") ") +
                               "is running this plan: wait for it or stop it (its tasks end with it)");
    }
    if (!own) return;
    const std::string text = std::string(kMark) + "\n" + std::to_string(::getpid()) + "\n";
    if (::ftruncate(fd_, 0) != 0 || ::write(fd_, text.data(), text.size()) != ssize_t(text.size()))
      throw std::runtime_error(file_.string() + ": cannot write");
  }
  PlanLock(const PlanLock&) = delete;
  PlanLock& operator=(const PlanLock&) = delete;
  ~PlanLock() { ::close(fd_); }

 private:
  static constexpr const char* kMark = "# occsweep cluster run-local: lock";

  // The pid on the lock's second line, "" when there is none.
  std::string holderPid() const {
    char text[128] = {};
    const ssize_t n = ::pread(fd_, text, sizeof text - 1, 0);
    std::string line = n > 0 ? std::string(text, std::size_t(n)) : "";
    line = line.substr(std::min(line.size(), line.find('\n') + 1));
    line = line.substr(0, line.find('\n'));
    return !line.empty() && line.find_first_not_of("0123456789") == std::string::npos ? line : "";
  }

  fs::path file_;
  int fd_ = -1;
};

/// Refuses while tasks of the plan run elsewhere: on Slurm, or started by a run-local that was killed and whose
/// tasks have not ended yet; they would write the same outputs as ours.
void refuseLiveTasks(const ClusterPlan& plan, const fs::path& dir) {
  const auto subs = readSubmissions(dir);
  std::size_t slurm = 0, local = 0;
  const auto status = planStatus(plan, dir, subs.empty() ? std::map<std::string, SlurmRecord>{} : querySlurm(subs), subs);
  for (const auto& row : status)
    for (const auto& t : row)
      if (t.state == TaskState::Running || t.state == TaskState::Pending)
        ++(t.detail.rfind("run-local pid ", 0) == 0 ? local : slurm);
  if (slurm)
    throw std::runtime_error(std::to_string(slurm) + " tasks of the plan are running or pending on Slurm: wait for "
                             "them (`cluster status DIR --wait`) or scancel them first");
  if (local)
    throw std::runtime_error(std::to_string(local) + " tasks of the plan are still running, started by an earlier "
                             "run-local (`cluster status DIR` lists their pids): wait for them to end");
}

fs::path logOf(const fs::path& dir, const ClusterStage& stage, const ClusterTask& t) {
  return dir / "logs" / ("local-" + stage.name + "-" + std::to_string(t.index) + ".log");
}

/// A task's log starts with this line: what marks it run-local's (a regular file with one name), replaced when the
/// task runs again; anything else at its name (a user's file, a link) is never removed or written, and no task
/// starts (docs/io.md, "Ownership").
constexpr const char* kTaskLogMark = "# occsweep cluster run-local: task log";

/// Why `logs` (the task logs at the names of tasks to run) stop run-local: each names an entry that is not a task log
/// run-local made; "" when none does.
std::string foreignTaskLogs(const std::vector<fs::path>& logs) {
  std::vector<std::string> foreign;
  std::error_code ec;
  for (const fs::path& log : logs)
    if (fs::exists(fs::symlink_status(log, ec)))
      if (const std::string why = notOwnReservedFile(log, kTaskLogMark); !why.empty())
        foreign.push_back(log.string() + " " + why);
  if (foreign.empty()) return "";
  std::string names = foreign.front();
  for (std::size_t i = 1; i < std::min<std::size_t>(foreign.size(), 5); ++i) names += "; " + foreign[i];
  if (foreign.size() > 5) names += "; and " + std::to_string(foreign.size() - 5) + " more";
  return names + ": " + (foreign.size() == 1 ? "it is" : "they are") + " not run-local's task log" +
         (foreign.size() == 1 ? "" : "s") + ", never replaced; move " + (foreign.size() == 1 ? "it" : "them") +
         " away and run again";
}

void startTaskLog(const fs::path& log, const std::string& label) {
  std::error_code ec;
  if (fs::exists(fs::symlink_status(log, ec))) {  // an earlier run's log, or run-local stops
    if (const std::string why = foreignTaskLogs({log}); !why.empty()) throw std::runtime_error(why);
    fs::remove(log);
  }
  const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
  if (fd < 0) throw std::runtime_error(log.string() + ": cannot create: " + std::strerror(errno));
  const std::string header = std::string(kTaskLogMark) + "\n# " + label + "\n";
  const bool written = ::write(fd, header.data(), header.size()) == ssize_t(header.size());
  ::close(fd);
  if (!written) throw std::runtime_error(log.string() + ": cannot write");
}

double cpuSeconds(const struct rusage& u) {
  return double(u.ru_utime.tv_sec) + double(u.ru_stime.tv_sec) + 1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

/// One stage's tasks while they run: which process runs which task in which stopper slot, and what has finished.
class StageRun {
 public:
  StageRun(const ClusterStage& stage, std::size_t tasks, const fs::path& dir, int jobs, TaskStopper& stopper,
           bool quiet)
      : stage_(stage), tasks_(tasks), dir_(dir), stopper_(stopper), start_(std::chrono::steady_clock::now()),
        last_print_(start_), quiet_(quiet) {
    for (std::size_t i = std::size_t(jobs); i-- > 0;) free_slots_.push_back(i);
  }

  [[nodiscard]] std::size_t running() const { return running_.size(); }
  [[nodiscard]] std::size_t failed() const { return failed_; }
  [[nodiscard]] double seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }

  /// Starts task `t` in a free slot, with its log and its running marker.
  void start(const ClusterTask& t) {
    const fs::path log = logOf(dir_, stage_, t);
    startTaskLog(log, t.label);
    const RunningMarker marker = createRunningMarker(dir_, stage_.name, t.index);  // before the process starts
    pid_t pid = 0;
    try {
      pid = spawnLogged(t.argv, dir_, log);
    } catch (...) {
      removeRunningMarker(marker);
      throw;
    }
    const std::size_t slot = free_slots_.back();
    free_slots_.pop_back();
    stopper_.track(slot, pid);
    running_[pid] = {t.index, slot, std::chrono::steady_clock::now(), marker};
    writeRunningMarker(marker, pid);
  }

  /// Waits for one task to end and checks its output; a signal returns at once.
  void reap() {
    for (;;) {
      int status = 0;
      struct rusage usage {};
      const pid_t pid = ::wait4(-1, &status, WNOHANG, &usage);
      if (pid < 0 && errno != EINTR) throw std::runtime_error(std::string("wait4 failed: ") + std::strerror(errno));
      if (pid > 0) return finish(pid, status, usage);
      if (pid < 0 || ::usleep(kPollMicroseconds) != 0) return;  // interrupted: the caller sees the signal
    }
  }

 private:
  // How often run-local looks for a task that has ended.
  static constexpr useconds_t kPollMicroseconds = 50'000;

  void finish(pid_t pid, int status, const struct rusage& usage) {
    const auto it = running_.find(pid);
    if (it == running_.end()) return;
    const ClusterTask& t = stage_.tasks[it->second.task];
    // The kernel's peak over the task's whole life (KiB on Linux): samples of /proc while it runs would miss what a
    // task does between two, and all of a task shorter than one (docs/cluster.md, "Measured tasks").
    const std::uint64_t peak = std::uint64_t(usage.ru_maxrss) * 1024;
    const TaskMeasurement measured{stage_.name, t.index, t.label, t.argv,
                                   std::chrono::duration<double>(std::chrono::steady_clock::now() -
                                                                 it->second.started).count(),
                                   cpuSeconds(usage), peak, exitCodeOf(status), false};
    stopper_.forget(it->second.slot);
    free_slots_.push_back(it->second.slot);
    removeRunningMarker(it->second.marker);
    running_.erase(it);
    if (stopper_.signal()) return;  // stopped: the task did not fail, it was ended
    ++finished_;
    const int code = exitCodeOf(status);
    const std::string why = code == 0 ? checkOutput(t, dir_) : "exit code " + std::to_string(code);
    record(measured, why.empty());
    if (!why.empty()) {
      ++failed_;
      std::cerr << "stage " << stage_.name << ": task " << t.index << " (" << t.label << ") failed: " << why
                << "; log " << logOf(dir_, stage_, t).string() << '\n';
    }
    printProgress();
  }

  // A measurement that cannot be written costs a warning, never the tasks still running.
  void record(TaskMeasurement m, bool succeeded) {
    m.succeeded = succeeded;
    try {
      appendMeasurement(dir_, m);
    } catch (const std::exception& e) {
      if (!measure_warned_) std::cerr << "warning: " << e.what() << ": task measurements are not recorded\n";
      measure_warned_ = true;
    }
  }

  // A line at most every few seconds, as tasks finish, not one per task: paper-scale stages have hundreds.
  void printProgress() {
    const auto now = std::chrono::steady_clock::now();
    if (quiet_ || (finished_ != tasks_ && now - last_print_ <= std::chrono::seconds(5))) return;
    const double seconds = std::chrono::duration<double>(now - start_).count();
    std::cerr << progressLine("stage " + stage_.name, "tasks", finished_, tasks_, seconds) << '\n';
    last_print_ = now;
  }

  struct Running {
    std::uint64_t task;
    std::size_t slot;
    std::chrono::steady_clock::time_point started;
    RunningMarker marker;
  };
  const ClusterStage& stage_;
  std::size_t tasks_;
  fs::path dir_;
  TaskStopper& stopper_;
  std::chrono::steady_clock::time_point start_, last_print_;
  bool quiet_;
  std::map<pid_t, Running> running_;
  std::vector<std::size_t> free_slots_;
  std::size_t finished_ = 0, failed_ = 0;
  bool measure_warned_ = false;
};

/// Runs the tasks `ids` of one stage, `jobs` at a time; returns how many failed (none counted once stopped).
std::size_t runStage(const ClusterStage& stage, const std::vector<std::uint64_t>& ids, const fs::path& dir, int jobs,
                     TaskStopper& stopper, bool quiet) {
  for (auto t : ids) requireOutputInside(stage.tasks[t], dir);  // before any task starts
  for (auto t : ids) removeOwnOutput(stage.tasks[t], dir);  // rewritten outputs must not count as done meanwhile
  StageRun run(stage, ids.size(), dir, jobs, stopper, quiet);
  std::size_t next = 0;
  while ((next < ids.size() && !stopper.signal()) || run.running() > 0) {
    while (next < ids.size() && run.running() < std::size_t(jobs) && !stopper.signal()) run.start(stage.tasks[ids[next++]]);
    if (stopper.signal()) stopper.stopAll();
    run.reap();
  }
  if (stopper.signal()) return 0;
  if (!quiet || run.failed())
    std::cerr << "stage " << stage.name << ": " << ids.size() - run.failed() << " of " << ids.size()
              << " tasks succeeded in " << run.seconds() << " s\n";
  return run.failed();
}

}  // namespace

namespace {
/// Before any task starts: a user's file at the log's name of a task to run stops run-local, every such file named.
void requireOwnTaskLogs(const ClusterPlan& plan, const std::vector<std::vector<std::uint64_t>>& torun,
                        const fs::path& dir) {
  std::vector<fs::path> logs;
  for (std::size_t s = 0; s < plan.stages.size(); ++s)
    for (const std::uint64_t id : torun[s]) logs.push_back(logOf(dir, plan.stages[s], plan.stages[s].tasks[id]));
  if (const std::string why = foreignTaskLogs(logs); !why.empty()) throw std::runtime_error(why);
}

/// Before any task starts: an entry at the running marker's name of a task to run, once occsweep's own stale markers
/// are gone, is a user's (removeStaleMarkers), and stops run-local.
void requireNoForeignMarkers(const ClusterPlan& plan, const std::vector<std::vector<std::uint64_t>>& torun,
                             const fs::path& dir) {
  for (std::size_t s = 0; s < plan.stages.size(); ++s)
    for (const std::uint64_t id : torun[s])
      if (const fs::path m = runningMarker(dir, plan.stages[s].name, id); fs::exists(fs::symlink_status(m)))
        throw std::runtime_error(foreignMarkerMessage(m));
}

}  // namespace

std::size_t runLocal(const ClusterPlan& plan, const fs::path& plan_dir, int jobs, bool quiet) {
  const fs::path dir = fs::absolute(plan_dir);  // tasks start in it, and logs open after that chdir
  if (jobs < 1) throw std::invalid_argument("--threads must be at least 1");
  for (const char* folder : {"logs", "running"}) {  // never written through a link to elsewhere
    if (fs::is_symlink(fs::symlink_status(dir / folder)))
      throw std::runtime_error((dir / folder).string() + ": is a symbolic link: run-local writes its task logs and "
                               "running markers inside the plan folder only; remove it");
    fs::create_directories(dir / folder);
  }
  const PlanLock lock(dir);
  refuseLiveTasks(plan, dir);
  removeStaleMarkers(dir);  // none is live
  // Otherwise what is done is what is on disk.
  const auto torun = tasksToRun(plan, planStatus(plan, dir, {}, {}));
  requireOwnTaskLogs(plan, torun, dir);
  requireNoForeignMarkers(plan, torun, dir);
  requireOwnMeasurements(dir);  // before any task starts
  TaskStopper stopper{std::size_t(jobs)};
  std::size_t failed = 0;
  for (std::size_t s = 0; s < plan.stages.size() && !stopper.signal(); ++s) {
    const ClusterStage& stage = plan.stages[s];
    const auto& ids = torun[s];
    if (ids.empty()) {
      if (!quiet) std::cerr << "stage " << stage.name << ": all " << stage.tasks.size() << " tasks done\n";
      continue;
    }
    const std::size_t stage_failed = runStage(stage, ids, dir, jobs, stopper, quiet);
    if (stopper.signal()) break;
    failed += stage_failed;
    if (stage_failed) {  // like afterok: later stages would read missing inputs
      std::cerr << "stopping: later stages need this one\n";
      break;
    }
  }
  if (const int signal = stopper.signal()) {
    std::cerr << "run-local: stopped by signal " << signal << " (" << strsignal(signal)
              << "); its tasks are ended, done tasks are kept. The rest runs with:\n  occsweep cluster run-local "
              << shownShellWord(plan_dir.string()) << " --threads " << jobs << (quiet ? " --quiet" : "") << '\n';
    // Die of the same signal, as the shell and a parent expect of a stopped program.
    ::signal(signal, SIG_DFL);
    ::raise(signal);
  }
  return failed;
}

}  // namespace occsweep
