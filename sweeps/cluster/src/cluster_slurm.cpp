// Talking to Slurm: reading its records of a plan's array tasks, and submitting stages as chained job arrays.
#include <map>
#include <set>
#include <sstream>

#include "occsweep/io/bounded_read.hpp"
#include "occsweep/sweeps/cluster_slurm.hpp"

namespace occsweep {
namespace fs = std::filesystem;
namespace {

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);)
    if (!l.empty()) out.push_back(l);
  return out;
}

std::vector<std::string> splitOn(const std::string& text, char sep) {
  std::vector<std::string> out;
  std::string cur;
  std::istringstream in(text);
  while (std::getline(in, cur, sep)) out.push_back(cur);
  return out;
}

bool numeric(const std::string& s) { return !s.empty() && s.find_first_not_of("0123456789") == std::string::npos; }

/// "CANCELLED by 0" -> "CANCELLED".
std::string firstWord(const std::string& s) { return s.substr(0, s.find(' ')); }

/// The stage's script on disk is the one this occsweep writes for the plan: a script of an earlier occsweep would run
/// task = array index, ignoring the offset of a split array, and one edited by hand is not the plan's.
void requireCurrentScript(const ClusterPlan& plan, const ClusterStage& stage, const fs::path& dir) {
  const fs::path script = dir / "slurm" / (stage.name + ".sbatch");
  std::string bytes;
  try {
    bytes = readFileBytes(script);  // a FIFO there is refused at once, never waited on
  } catch (const std::exception& e) {
    throw std::runtime_error(std::string(e.what()) + " (the stage's script): move away what stands at that name, "
                             "write the plan again with the same `occsweep cluster plan` command, then submit "
                             "(nothing was submitted)");
  }
  if (bytes != sbatchScript(plan, stage))
    throw std::runtime_error(script.string() + ": not the script this occsweep writes for the plan (one an earlier "
                             "occsweep wrote, or edited by hand): write the plan again with the same `occsweep "
                             "cluster plan` command, which replaces occsweep's own scripts, then submit (nothing "
                             "was submitted)");
}

/// Slurm's MaxArraySize (an array index must be below it): the plan's, else what `scontrol show config` says, else
/// Slurm's default, 1001.
std::uint64_t maxArraySize(const SlurmOptions& o) {
  if (o.max_array_size > 0) return o.max_array_size;
  const auto r = runCapture({"scontrol", "show", "config"}, true);
  if (r.exit_code == 0)
    for (const auto& l : lines(r.text)) {
      std::istringstream words(l);  // "MaxArraySize            = 1001"
      std::string key, equals, value;
      if (words >> key >> equals >> value && key == "MaxArraySize" && equals == "=" && numeric(value) &&
          value.size() < 10 && std::stoull(value) > 0)
        return std::stoull(value);
    }
  return 1001;
}

/// One array of a stage: its tasks, each at array index task - offset.
struct ArrayPart {
  std::uint64_t offset = 0;
  std::vector<std::uint64_t> tasks;
};

/// The tasks `ids` (ascending) in arrays whose indices stay below `max_size`: task t goes to the array of offset
/// t - t % max_size, at index t % max_size. A stage of fewer tasks than MaxArraySize is one array of offset 0.
std::vector<ArrayPart> splitArrays(const std::vector<std::uint64_t>& ids, std::uint64_t max_size) {
  std::vector<ArrayPart> parts;
  for (const std::uint64_t id : ids) {
    const std::uint64_t offset = id - id % max_size;
    if (parts.empty() || parts.back().offset != offset) parts.push_back({offset, {}});
    parts.back().tasks.push_back(id);
  }
  return parts;
}

/// sbatch's --array of one part: its indices, then `%N` under a throttle.
std::string arrayOption(const ArrayPart& part, std::uint64_t throttle) {
  std::vector<std::uint64_t> indices;
  for (const std::uint64_t t : part.tasks) indices.push_back(t - part.offset);
  return arrayRanges(indices) + (throttle > 0 ? "%" + std::to_string(throttle) : "");
}

/// One sbatch of `part` of a stage, after the arrays of `deps` (":JOB:JOB..."): recorded in submissions.jsonl and
/// the report, said on `log`. Returns its job id.
std::string submitArray(const ClusterPlan& plan, const ClusterStage& stage, const ArrayPart& part,
                        const std::string& deps, const fs::path& dir, SubmitReport& report, std::ostream& log) {
  const std::string array = arrayOption(part, plan.slurm.array_throttle);
  std::vector<std::string> argv = {"sbatch", "--parsable", "--array=" + array,
                                   "--export=ALL,OCCSWEEP_TASK_OFFSET=" + std::to_string(part.offset),
                                   "--chdir=" + fs::absolute(dir).string(),
                                   "--output=" + (fs::absolute(dir) / "logs" / (stage.name + "-%A_%a.out")).string()};
  if (!deps.empty()) {
    argv.push_back("--dependency=afterok" + deps);
    argv.push_back("--kill-on-invalid-dep=yes");  // a failed dependency cancels this array, not leaves it pending
  }
  argv.push_back((fs::absolute(dir) / "slurm" / (stage.name + ".sbatch")).string());
  const auto r = runCapture(argv);
  const auto got = lines(r.text);
  const std::string job = got.empty() ? "" : firstWord(splitOn(got.back(), ';')[0]);
  if (r.exit_code != 0 || !numeric(job))
    throw std::runtime_error("sbatch of stage " + stage.name + " failed (exit " + std::to_string(r.exit_code) + ")" +
                             (report.submitted.empty() ? "" : ": earlier arrays were submitted, see status"));
  const Submission sub{stage.name, job, part.tasks, part.offset};
  appendSubmission(dir, sub);
  report.submitted.push_back(sub);
  log << "stage " << stage.name << ": job " << job << ", " << part.tasks.size() << " of " << stage.tasks.size()
      << " tasks (--array=" << array << (part.offset ? ", tasks from " + std::to_string(part.offset) : "") << ")"
      << (deps.empty() ? "" : ", after " + deps.substr(1)) << '\n';
  return job;
}

}  // namespace

std::map<std::string, SlurmRecord> querySlurm(const std::vector<Submission>& submissions) {
  std::map<std::string, SlurmRecord> out;
  std::set<std::string> jobs;
  for (const auto& s : submissions) jobs.insert(s.job_id);
  for (const auto& job : jobs) {
    std::map<std::string, SlurmRecord> live, kept, accounted;
    // Live tasks, one line each (-r), pending ones too: "12_3|PENDING|Dependency".
    const auto q = runCapture({"squeue", "-h", "-r", "-j", job, "-o", "%i|%T|%r"}, true);
    if (q.exit_code == 0)
      for (const auto& l : lines(q.text)) {
        const auto f = splitOn(l, '|');
        if (f.size() >= 3 && f[0].rfind(job + "_", 0) == 0 && numeric(f[0].substr(job.size() + 1)))
          live[f[0]] = {f[1], f[2]};
      }
    // Finished tasks while slurmctld keeps them (MinJobAge): "... ArrayJobId=12 ArrayTaskId=3 ... JobState=FAILED".
    const auto c = runCapture({"scontrol", "-o", "show", "job", job}, true);
    if (c.exit_code == 0)
      for (const auto& l : lines(c.text)) {
        std::string array_job, task, state, reason;
        for (const auto& tok : splitOn(l, ' ')) {
          const auto eq = tok.find('=');
          if (eq == std::string::npos) continue;
          const std::string key = tok.substr(0, eq), value = tok.substr(eq + 1);
          if (key == "ArrayJobId") array_job = value;
          else if (key == "ArrayTaskId") task = value;
          else if (key == "JobState") state = value;
          else if (key == "Reason") reason = value;
        }
        if (array_job == job && numeric(task)) kept[job + "_" + task] = {state, reason};
      }
    // Accounting, where slurmdbd runs (real clusters keep records long after MinJobAge).
    const auto a = live.empty() && kept.empty()
                       ? runCapture({"sacct", "-n", "-P", "-X", "-j", job, "-o", "JobID,State"}, true)
                       : ProcessOutput{};
    if (a.exit_code == 0)
      for (const auto& l : lines(a.text)) {
        const auto f = splitOn(l, '|');
        if (f.size() >= 2 && f[0].rfind(job + "_", 0) == 0 && numeric(f[0].substr(job.size() + 1)))
          accounted[f[0]] = {firstWord(f[1]), ""};
      }
    for (auto* m : {&accounted, &kept, &live})
      for (auto& [k, v] : *m) out[k] = v;  // later sources win: live over kept over accounted
  }
  return out;
}

SubmitReport submitPlan(const ClusterPlan& plan, const fs::path& dir, bool resubmit, std::ostream& log) {
  SubmitReport report;
  for (const ClusterStage& stage : plan.stages) requireCurrentScript(plan, stage, dir);  // before anything is sent
  const auto subs = readSubmissions(dir);
  if (!resubmit && !subs.empty())
    throw std::runtime_error((dir / "submissions.jsonl").string() + ": the plan was submitted already (" +
                             std::to_string(subs.size()) + " arrays): use `cluster status` and `cluster resubmit`");
  auto records = querySlurm(subs);
  // Tasks waiting on a dependency that failed never start: cancel them, they are submitted again below.
  for (auto& [id, rec] : records)
    if (rec.state == "PENDING" && rec.reason == "DependencyNeverSatisfied") {
      (void)runCapture({"scancel", id}, true);
      report.cancelled.push_back(id);
      rec = {"CANCELLED", "resubmit"};
    }
  const auto status = planStatus(plan, dir, records, subs);
  std::size_t live = 0;
  for (const auto& row : status)
    for (const auto& t : row) live += t.state == TaskState::Running || t.state == TaskState::Pending;
  if (live)
    throw std::runtime_error(std::to_string(live) + " tasks of the plan are still running or pending: wait for them "
                             "(`cluster status DIR --wait`) or scancel them, then resubmit");
  const auto torun = tasksToRun(plan, status);
  const std::uint64_t max_size = maxArraySize(plan.slurm);
  std::map<std::string, std::string> submitted;  // stage -> ":JOB:JOB..." of its arrays, this round
  for (std::size_t s = 0; s < plan.stages.size(); ++s) {
    const ClusterStage& stage = plan.stages[s];
    if (torun[s].empty()) continue;
    // An output that is rewritten must not be taken as done meanwhile (a sweep keeps a complete file).
    for (auto t : torun[s]) requireOutputInside(stage.tasks[t], dir);
    for (auto t : torun[s]) removeOwnOutput(stage.tasks[t], dir);
    std::string deps;
    for (const auto& a : stage.after) deps += submitted[a];
    for (const ArrayPart& part : splitArrays(torun[s], max_size))
      submitted[stage.name] += ":" + submitArray(plan, stage, part, deps, dir, report, log);
  }
  if (report.submitted.empty()) log << "nothing to submit: every task is done\n";
  return report;
}

}  // namespace occsweep
