// Where a plan stands: outputs on disk (the truth about "done") and Slurm's records (running, pending, failed).
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <sys/types.h>
#include <vector>

#include "occsweep/io/child_process.hpp"  // exitCodeOf and runCapture, for the callers of spawnLogged
#include "occsweep/sweeps/cluster_plan.hpp"

namespace occsweep {

// ---- run-local's tasks (cluster_exec.cpp; Slurm's clients run through eval's runCapture) ----
/// Starts argv in `cwd` with stdout and stderr appended to `log`; returns the pid (std::runtime_error on failure).
/// The child gets SIGTERM when this process dies, even by SIGKILL (PR_SET_PDEATHSIG): run-local's tasks never
/// outlive it (docs/cluster.md); an argv[0] that cannot be started is exit code 127 with the reason in the log.
[[nodiscard]] pid_t spawnLogged(const std::vector<std::string>& argv, const std::filesystem::path& cwd,
                                const std::filesystem::path& log);

// ---- run-local's running tasks ----
/// DIR/running/<stage>-<task>.pid: the pid of the process run-local started for the task, while it runs.
[[nodiscard]] std::filesystem::path runningMarker(const std::filesystem::path& dir, const std::string& stage,
                                                 std::uint64_t task);
/// A marker run-local made for a task it starts, known by its entry: removed only while it is that entry.
struct RunningMarker {
  std::filesystem::path path;
  dev_t device = 0;
  ino_t inode = 0;
};
/// Why run-local stops at an entry standing at a marker's name that is not a stale marker of its own.
[[nodiscard]] std::string foreignMarkerMessage(const std::filesystem::path& marker);
/// Makes the task's marker, holding its mark line, where nothing stands (never over or through another entry): before
/// the task's process starts. std::runtime_error naming the marker when an entry stands there.
[[nodiscard]] RunningMarker createRunningMarker(const std::filesystem::path& dir, const std::string& stage,
                                                std::uint64_t task);
/// Appends the task's pid to its marker, while it is the entry createRunningMarker made.
void writeRunningMarker(const RunningMarker& marker, pid_t pid);
/// Removes the marker while it is the entry createRunningMarker made; anything put at its name since stays.
void removeRunningMarker(const RunningMarker& marker);
/// Removes the markers in DIR/running that a killed run-local left (their tasks are not live: checked before): a
/// regular file with one name that starts with the marker's mark line; any other entry stays (docs/io.md,
/// "Ownership").
void removeStaleMarkers(const std::filesystem::path& dir);
/// The pid in the task's marker when that process is alive (not a zombie) and runs in DIR; 0 otherwise (no
/// marker, or one left by a run-local killed with SIGKILL whose task has ended since).
[[nodiscard]] pid_t liveLocalTask(const std::filesystem::path& dir, const std::string& stage, std::uint64_t task);

// ---- outputs ----
/// Empty when the task's output is valid, else why not ("missing", "incomplete results", ...).
[[nodiscard]] std::string checkOutput(const ClusterTask& task, const std::filesystem::path& dir);
/// Before a task runs again: removes its output when it is a file inside DIR (links resolved) that passes
/// checkOutput, i.e. occsweep's own earlier output, so that it is not taken as done meanwhile; never an `exists`
/// output, which no check proves occsweep's. Anything else stays for the task's own --force rule to refuse
/// (docs/cluster.md, "Outputs stay in the plan folder").
void removeOwnOutput(const ClusterTask& task, const std::filesystem::path& dir);
/// Throws naming the output when it leads out of DIR, through a symbolic link on its way (a linked `merged/`): a task
/// writes only inside its plan folder (docs/cluster.md, "Outputs stay in the plan folder").
void requireOutputInside(const ClusterTask& task, const std::filesystem::path& dir);
/// True when the output is older than one of its inputs (an input was redone after it).
[[nodiscard]] bool outputStale(const ClusterTask& task, const std::filesystem::path& dir);

// ---- Slurm records ----
/// One `sbatch` of a stage's tasks, an array, appended to DIR/submissions.jsonl: its tasks, task t at array index
/// t - offset (a stage's arrays stay within MaxArraySize). A record without an offset (an earlier occsweep's) has 0.
struct Submission {
  std::string stage, job_id;
  std::vector<std::uint64_t> tasks;
  std::uint64_t offset = 0;
};
[[nodiscard]] std::vector<Submission> readSubmissions(const std::filesystem::path& dir);
void appendSubmission(const std::filesystem::path& dir, const Submission& s);

/// What a task cost when run-local ran it (docs/cluster.md, "Measured tasks"): one line of DIR/measured.jsonl.
struct TaskMeasurement {
  std::string stage;
  std::uint64_t task = 0;
  std::string label;
  std::vector<std::string> argv;             ///< the command it ran: a measurement counts for this command only
  double wall_seconds = 0, cpu_seconds = 0;  ///< CPU: user + system, of the task and the children it waited for
  std::uint64_t peak_bytes = 0;              ///< peak resident memory of the task's process (VmHWM, read every 50 ms)
  int exit_code = 0;
  bool succeeded = false;                    ///< exit 0 and an output that passes the task's check
};
/// Appends `m` to DIR/measured.jsonl (never through a symbolic link at its name; std::runtime_error otherwise).
void appendMeasurement(const std::filesystem::path& dir, const TaskMeasurement& m);
/// DIR/measured.jsonl in file order (none: empty); a broken line, or a number out of its range (times finite and
/// from 0 to 10^9 s, memory below 2^50 bytes), is refused naming the file and the line, and so is a file that is not
/// a regular file or larger than 1 GB.
[[nodiscard]] std::vector<TaskMeasurement> readMeasurements(const std::filesystem::path& dir);

/// Each task's last successful run (exit 0, its output checked) in `measurements`, found for a task of a plan only
/// when it ran that task's own command (a line of another command at that index, an earlier plan's, is not its).
class LastSuccesses {
 public:
  explicit LastSuccesses(const std::vector<TaskMeasurement>& measurements);
  /// The measurement of `task` of `stage`; nullptr when none.
  [[nodiscard]] const TaskMeasurement* of(const std::string& stage, const ClusterTask& task) const;

 private:
  std::map<std::pair<std::string, std::uint64_t>, const TaskMeasurement*> last_;  // (stage, task) -> its last success
};

/// A stage's cost as run-local measured it: each task's last successful run (exit 0, its output checked) of the
/// task's own command (a measurement of another command at that index, an earlier plan's, is left out).
struct MeasuredStage {
  std::string stage;
  std::size_t tasks = 0, measured = 0;        ///< the stage's tasks, and how many have a measurement
  double wall_seconds = 0, longest_seconds = 0, cpu_seconds = 0;  ///< sums but the longest task's wall time
  std::uint64_t peak_bytes = 0;               ///< the largest task's peak resident memory
};
[[nodiscard]] std::vector<MeasuredStage> measuredStages(const ClusterPlan& plan,
                                                        const std::vector<TaskMeasurement>& measurements);

/// What Slurm says about array tasks, keyed "JOBID_TASK": state (RUNNING, FAILED, ...) and pending reason.
struct SlurmRecord {
  std::string state, reason;
};
/// squeue for live tasks, then `scontrol show job` (finished tasks kept MinJobAge seconds), then sacct (where
/// accounting runs). Tasks none of them knows are absent.
[[nodiscard]] std::map<std::string, SlurmRecord> querySlurm(const std::vector<Submission>& submissions);

// ---- status ----
enum class TaskState { Done, Running, Pending, Failed, Stale, Invalid, Missing };
[[nodiscard]] const char* stateName(TaskState s);

struct TaskStatus {
  TaskState state = TaskState::Missing;
  std::string detail;    ///< why not done
  std::string slurm_id;  ///< JOBID_TASK of its latest submission, if any
};

/// Per stage, per task. Live Slurm tasks are Running/Pending whatever their output, and so are tasks a run-local
/// is running (liveLocalTask, detail "run-local pid N"); otherwise a valid, fresh
/// output is Done; a task whose latest Slurm record ended badly (or ended COMPLETED without a valid output) is
/// Failed; an output that exists but does not pass is Invalid; an output older than an input is Stale.
[[nodiscard]] std::vector<std::vector<TaskStatus>> planStatus(const ClusterPlan& plan, const std::filesystem::path& dir,
                                                              const std::map<std::string, SlurmRecord>& records,
                                                              const std::vector<Submission>& submissions);

/// Tasks to run again, per stage: every task not Done, Running or Pending, and every task downstream of one
/// (its input will be rewritten, so its output would go stale).
[[nodiscard]] std::vector<std::vector<std::uint64_t>> tasksToRun(const ClusterPlan& plan,
                                                                 const std::vector<std::vector<TaskStatus>>& status);

/// "0-3,7,9-10": Slurm's --array syntax for sorted ids.
[[nodiscard]] std::string arrayRanges(const std::vector<std::uint64_t>& ids);

}  // namespace occsweep
