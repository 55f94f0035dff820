// occsweep cluster plan|submit|status|resubmit|run-local: sharded experiments as Slurm job arrays (docs/cluster.md).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <iostream>
#include <sched.h>
#include <sstream>
#include <thread>

#include "command_registry.hpp"
#include "install_paths.hpp"
#include "option_checks.hpp"
#include "task_options.hpp"
#include "occsweep/sweeps/cluster_estimate.hpp"
#include "occsweep/sweeps/cluster_select.hpp"
#include "occsweep/sweeps/cluster_slurm.hpp"
#include "occsweep/sweeps/progress.hpp"
#include "occsweep/io/control_characters.hpp"

namespace occsweep::cli {
namespace {

/// Core-hours of `cpu_seconds`, to three significant digits (0.00436, 39.2, 1234).
std::string coreHours(double cpu_seconds) {
  const double hours = cpu_seconds / 3600.0;
  char text[32];
  std::snprintf(text, sizeof text, hours >= 100 ? "%.0f" : "%.3g", hours);
  return text;
}

/// What run-local measured of each stage (docs/cluster.md, "Measured tasks"); nothing when it measured nothing.
void printMeasured(const std::vector<MeasuredStage>& stages, const std::filesystem::path& dir) {
  if (std::none_of(stages.begin(), stages.end(), [](const MeasuredStage& s) { return s.measured > 0; })) return;
  std::cout << "measured by run-local (" << (dir / "measured.jsonl").string()
            << ", each task's last successful run):\n";
  for (const MeasuredStage& s : stages) {
    if (s.measured == 0) continue;
    std::ostringstream line;
    line.setf(std::ios::fixed);
    line.precision(1);
    line << "  stage " << s.stage << ": " << s.measured << " of " << s.tasks << " tasks, wall " << s.wall_seconds
         << " s in all (longest " << s.longest_seconds << " s), CPU " << s.cpu_seconds << " s ("
         << coreHours(s.cpu_seconds) << " core-hours), peak memory " << std::setprecision(0)
         << double(s.peak_bytes) / 1e6 << " MB\n";
    std::cout << line.str();
  }
}

/// Prints the status; returns the number of tasks not done and counts live ones (running, pending that can start).
std::size_t printStatus(const ClusterPlan& plan, const std::filesystem::path& dir, bool all, bool quiet,
                        std::size_t* live) {
  const auto subs = readSubmissions(dir);
  const auto records = querySlurm(subs);
  const auto status = planStatus(plan, dir, records, subs);
  std::size_t not_done = 0;
  *live = 0;
  for (std::size_t s = 0; s < plan.stages.size(); ++s) {
    std::map<TaskState, std::size_t> count;
    for (const auto& t : status[s]) {
      ++count[t.state];
      if ((t.state == TaskState::Running || t.state == TaskState::Pending) && t.detail != "DependencyNeverSatisfied")
        ++*live;
    }
    not_done += status[s].size() - count[TaskState::Done];
    if (quiet) continue;
    std::cout << "stage " << plan.stages[s].name << ": " << status[s].size() << " tasks:";
    for (auto st : {TaskState::Done, TaskState::Running, TaskState::Pending, TaskState::Failed, TaskState::Stale,
                    TaskState::Invalid, TaskState::Missing})
      std::cout << ' ' << count[st] << ' ' << stateName(st) << (st == TaskState::Missing ? "" : ",");
    std::cout << '\n';
    std::size_t shown = 0;
    for (std::size_t i = 0; i < status[s].size(); ++i) {
      const auto& t = status[s][i];
      if (t.state == TaskState::Done && !all) continue;
      if (!all && ++shown > 20) {
        std::cout << "  ... (--all lists every task)\n";
        break;
      }
      const auto& task = plan.stages[s].tasks[i];
      std::cout << "  " << stateName(t.state) << ' ' << plan.stages[s].name << '[' << i << "] " << task.label
                << (t.slurm_id.empty() ? "" : " job " + t.slurm_id) << " -> " << task.output
                << (t.detail.empty() ? "" : ": " + t.detail) << '\n';
    }
  }
  if (!quiet) {
    try {
      printMeasured(measuredStages(plan, readMeasurements(dir)), dir);
    } catch (const std::exception& e) {  // the status stands without them
      std::cerr << "warning: " << e.what() << ": measurements not shown\n";
    }
  }
  return not_done;
}

using Subcommand = std::pair<CLI::App*, std::function<int()>>;

/// `cluster plan`'s options: the plan's configuration and what is read before buildPlan sees it.
struct PlanOptions {
  PlanConfig config;
  std::string dir, kind = "exists";
  std::vector<std::string> grids, sweep_args, mem, time;  // --mem, --time: VALUE or STAGE=VALUE
  std::string estimate_from;  // a plan folder run-local has measured
  bool force = false;
  std::vector<std::string> dataset_dirs, dataset_names;
  CLI::Option *blocks = nullptr, *unranked = nullptr, *sets = nullptr, *group_set = nullptr;
};

/// The generation and selection options of `cluster plan`.
void addPlanDataOptions(CLI::App& plan, PlanOptions& o) {
  PlanConfig& c = o.config;
  plan.add_option("--dataset", o.dataset_dirs, "--experiment sweep: a data-set folder to sweep (repeatable)")
      ->type_name(kPath);
  plan.add_option("--name", o.dataset_names, "--experiment reproduce: a paper data set to generate and sweep "
                                             "(repeatable; default the paper's 20)");
  plan.add_option("--generate", c.generate, "Generation command, occsweep arguments; {dataset} {index} {seed} {block} {blocks} {out} {scale}")
      ->capture_default_str();
  plan.add_option("--generate-out", c.generate_out, "What one generation task writes, relative to the plan folder")
      ->type_name(kPath)->capture_default_str();
  plan.add_option("--generate-kind", o.kind, "How a generation output is checked")
      ->check(CLI::IsMember({"exists", "dataset"}))->capture_default_str();
  plan.add_option("--scale", c.scale, "{scale} of the generation command")->capture_default_str();
  o.blocks = plan.add_option("--blocks", c.blocks, "Generation shards per data set: blocks of point cloud parameter ids ({pcs})")
      ->capture_default_str()->check(integerAtLeast<std::uint64_t>(1));
  plan.add_option("--pcs-count", c.pcs_count, "Point cloud parameter ids 0..N-1 to generate")->capture_default_str()->check(integerAtLeast<std::uint64_t>(1));
  // Read through count(): no bound variable, which would have to outlive parsing (ASan caught a freed one).
  o.unranked = plan.add_flag("--unranked")->description("No select stage: sweep folders under the generated "
                                                        "output itself (defaults then: --blocks 1 --sets . --group-set '')");
  o.sets = plan.add_option("--sets", c.sets, "Point cloud sets to sweep, per data set: rank-N or pcs-NNNN (ranked), or "
                                             "folders relative to the data set ('.': itself, the default of "
                                             "--experiment sweep)")
      ->delimiter(',')->capture_default_str();
  o.group_set = plan.add_option("--group-set", c.group_set, "The set that grouped grids sweep")->capture_default_str();
}

/// The sweep and sbatch options of `cluster plan`.
void addPlanRunOptions(CLI::App& plan, PlanOptions& o) {
  PlanConfig& c = o.config;
  plan.add_option("--grid", o.grids, "NAME[:SHARDS[:grouped]] (repeatable), grouped: data set i sweeps Eq. 16 group i of "
                                     "the data sets (default octomap-opt:1, knn-opt:4, and reduction:4:grouped for "
                                     "reproduce)");
  plan.add_option("--seed", c.group_seed, "Eq. 16 permutation seed of grouped grids")->capture_default_str();
  plan.add_option("--threads", c.sweep_threads, "--threads of each sweep (0: --cpus-per-task)")->capture_default_str()
      ->check(threadCount());
  plan.add_option("--sweep-args", o.sweep_args, "More `occsweep sweep` settings for every sweep, e.g. --s-c,4")->delimiter(',');
  plan.add_option("--occsweep", c.occsweep, "occsweep binary the tasks run (default: this one)")->type_name(kPath);
  plan.add_option("--cpus-per-task", c.slurm.cpus_per_task, "sbatch --cpus-per-task")->capture_default_str()->check(integerAtLeast<int>(1));
  plan.add_option("--mem", o.mem, "sbatch --mem: VALUE for every stage, or STAGE=VALUE for one (repeatable)")
      ->default_str(c.slurm.mem);
  plan.add_option("--time", o.time, "sbatch --time: VALUE for every stage, or STAGE=VALUE for one (repeatable)")
      ->default_str(c.slurm.time);
  plan.add_option("--setup", c.slurm.setup, "A shell line every task runs first, e.g. 'module load gcc' (repeatable)");
  plan.add_option("--array-throttle", c.slurm.array_throttle, "At most this many tasks of an array at once "
                  "(sbatch --array=...%N; 0: no limit)")->capture_default_str()
      ->check(integerIn<std::uint64_t>(0, kMaxArrayThrottle));
  plan.add_option("--estimate-from", o.estimate_from, "A plan folder run-local ran: print what this plan will cost "
                  "from its measured tasks, and set each stage's --time and --mem from it unless given")
      ->type_name(kPath);
  plan.add_option("--max-array-size", c.slurm.max_array_size, "Slurm's MaxArraySize: larger stages are submitted as "
                  "several arrays (0: read from scontrol show config at submit, else 1001)")->capture_default_str()
      ->check(integerIn<std::uint64_t>(0, kMaxArraySizeLimit));
  plan.add_option("--partition", c.slurm.partition, "sbatch --partition");
  plan.add_option("--account", c.slurm.account, "sbatch --account");
  plan.add_option("--sbatch", c.slurm.extra, "More #SBATCH options, verbatim (repeatable), e.g. --qos=long");
}

/// --dataset names folders (sweep), --name the paper's data sets (reproduce): the other one is refused.
std::vector<std::string> plannedDatasets(const PlanOptions& o) {
  const bool sweep = o.config.experiment == "sweep";
  if (sweep && !o.dataset_names.empty())
    throw CLI::ValidationError("--name", "names a paper data set to generate, which --experiment sweep does not: give "
                                         "the data-set folders with --dataset");
  if (!sweep && !o.dataset_dirs.empty())
    throw CLI::ValidationError("--dataset", "names a data-set folder to sweep, which --experiment reproduce does not "
                                            "(it generates its data): give paper data sets with --name, or use "
                                            "--experiment sweep");
  return sweep ? o.dataset_dirs : o.dataset_names;
}

/// Tasks run on compute nodes, which see only shared file systems: a path on a local one (a build folder under /tmp)
/// is named, with what to do (docs/cluster.md). run-local does not mind.
void warnIfLocal(const std::filesystem::path& path, const std::string& what, const std::string& fix) {
  if (const auto fs_name = localFileSystemOf(path))
    std::cerr << "warning: " << what << ", " << path.string() << ", is on a file system local to this machine ("
              << *fs_name << "): Slurm's compute nodes may not see it. On a cluster, " << fix
              << ". run-local works as it is.\n";
}

/// Whether `given` (--mem or --time as typed) sets every stage's value, or `stage`'s own.
bool givenFor(const std::vector<std::string>& given, const std::string& stage) {
  return std::any_of(given.begin(), given.end(), [&](const std::string& v) {
    return v.find('=') == std::string::npos || v.rfind(stage + "=", 0) == 0;
  });
}

/// A stage whose every task the estimate models gets --time and --mem from it, with their margins, unless they were
/// given (docs/cluster.md, "Cost estimate").
void applyEstimatedLimits(const std::vector<StageEstimate>& estimate, const PlanOptions& o, SlurmOptions& slurm) {
  for (const StageEstimate& e : estimate) {
    if (e.modelled == 0 || e.modelled != e.tasks) continue;
    if (!givenFor(o.time, e.stage)) slurm.stage_time[e.stage] = timeWithMargin(e.longest_seconds);
    if (!givenFor(o.mem, e.stage)) slurm.stage_mem[e.stage] = memWithMargin(e.peak_bytes);
  }
}

/// The cores this process may run on (its CPU affinity, as nproc counts them; at least 1).
int usableCores() {
  cpu_set_t set;
  if (::sched_getaffinity(0, sizeof set, &set) == 0) return std::max(1, CPU_COUNT(&set));
  return int(std::max(1u, std::thread::hardware_concurrency()));
}

void printEstimate(const std::vector<StageEstimate>& estimate, const std::string& from, const SlurmOptions& slurm) {
  std::cout << "estimate from the tasks run-local measured in " << from
            << " (each kind of task costs the mean of its measured runs, the report per results file it compares; "
               "docs/cluster.md, \"Cost estimate\"):\n";
  double cpu = 0;
  std::size_t unmodelled = 0;
  for (const StageEstimate& e : estimate) {
    cpu += e.cpu_seconds;
    unmodelled += e.tasks - e.modelled;
    std::cout << "  stage " << e.stage << ": " << e.tasks << " tasks";
    if (e.modelled == 0) {
      std::cout << ", none of a kind measured there\n";
      continue;
    }
    if (e.modelled != e.tasks) std::cout << " (" << e.modelled << " of a kind measured)";
    std::cout << ", " << coreHours(e.cpu_seconds) << " core-hours, longest task " << durationText(e.longest_seconds)
              << ", peak memory " << long(std::lround(double(e.peak_bytes) / 1e6)) << " MB; --time "
              << stageTime(slurm, e.stage) << " --mem " << stageMem(slurm, e.stage) << '\n';
  }
  std::cout << "  in all: " << coreHours(cpu) << " core-hours";
  // The cores this process may use too (its affinity, as nproc counts them): what run-local takes here with as many
  // tasks at once as fit.
  const int here = usableCores();
  std::vector<int> counts = {64, 256};
  if (here != 64 && here != 256) counts.insert(counts.begin(), here);
  for (const int cores : counts) {
    std::cout << "; on " << cores << " cores";
    if (cores == here)
      std::cout << " (here: run-local --threads " << std::max(1, here / std::max(1, slurm.cpus_per_task)) << ')';
    std::cout << " about " << durationText(estimatedWallSeconds(estimate, cores, slurm.cpus_per_task));
  }
  std::cout << (unmodelled ? " (without the " + std::to_string(unmodelled) + " tasks of kinds not measured)" : "")
            << '\n';
}

/// Without a measured run there is no estimate: say so, with the limits every stage got and how to get one.
void printNoEstimate(const ClusterPlan& p) {
  std::cout << "cost: not estimated (no --estimate-from); each stage's limits, given or the defaults:\n";
  for (const ClusterStage& s : p.stages)
    std::cout << "  stage " << s.name << ": --time " << stageTime(p.slurm, s.name) << " --mem "
              << stageMem(p.slurm, s.name) << '\n';
  std::cout << "to estimate the cost and set the limits from it, run a smaller plan of the same shape (fewer data "
               "sets)\nwith `occsweep cluster run-local` and plan again with --estimate-from ITS_FOLDER (docs/cluster.md, "
               "\"Cost estimate\")\n";
}

int runPlan(const PlanOptions& o) {
  PlanConfig c = o.config;
  c.ranked = o.unranked->count() == 0;
  if (!o.grids.empty()) {
    c.grids.clear();
    for (const auto& text : o.grids) c.grids.push_back(parsePlanGrid(text));
  }
  c.datasets = plannedDatasets(o);
  applyPlanDefaults(c, {!c.datasets.empty(), !o.grids.empty(), o.sets->count() > 0, o.group_set->count() > 0,
                        o.blocks->count() > 0});
  const std::filesystem::path binary = c.occsweep.empty() ? runningBinary() : std::filesystem::path(c.occsweep);
  c.occsweep = std::filesystem::absolute(binary).string();
  c.sweep = sharedSweepSettings(o.sweep_args);
  c.generate_kind = kindFromName(o.kind);
  parseStageValues(o.mem, "--mem", c.slurm.mem, c.slurm.stage_mem);
  parseStageValues(o.time, "--time", c.slurm.time, c.slurm.stage_time);
  ClusterPlan p = buildPlan(c);
  std::vector<StageEstimate> estimate;
  if (!o.estimate_from.empty()) {
    const ClusterPlan measured_plan = readPlan(o.estimate_from);
    const std::vector<TaskMeasurement> measured = readMeasurements(o.estimate_from);
    if (std::none_of(measured.begin(), measured.end(), [](const TaskMeasurement& m) { return m.succeeded; }))
      throw std::invalid_argument("--estimate-from " + o.estimate_from + ": no task of that plan has run to success "
                                  "under run-local (" + o.estimate_from + "/measured.jsonl): run `occsweep cluster "
                                  "run-local " + o.estimate_from + "` first");
    if (measured_plan.slurm.cpus_per_task != p.slurm.cpus_per_task)
      std::cerr << "warning: --estimate-from " << o.estimate_from << " ran its tasks with --cpus-per-task "
                << measured_plan.slurm.cpus_per_task << ", this plan with " << p.slurm.cpus_per_task
                << ": the times carried over are that plan's\n";
    estimate = estimatePlan(p, measured_plan, measured);
    applyEstimatedLimits(estimate, o, p.slurm);
  }
  writePlan(p, o.dir, o.force);
  warnIfLocal(p.occsweep, "the occsweep binary the tasks run",
              "install occsweep on a shared file system (NFS, Lustre, GPFS, BeeGFS, CephFS) and plan with that "
              "binary, or give --occsweep PATH");
  warnIfLocal(o.dir, "the plan folder",
              "plan into a folder on a shared file system: the tasks run in it and write their outputs under it");
  std::size_t total = 0;
  for (const auto& s : p.stages) {
    std::cout << "stage " << s.name << ": " << s.tasks.size() << " tasks"
              << (s.after.empty() ? "" : " (after " + s.after[0] + ")") << ", "
              << escapedControlCharacters(o.dir + "/slurm/" + s.name + ".sbatch") << "\n";
    total += s.tasks.size();
  }
  std::cout << "wrote " << escapedControlCharacters(o.dir + "/plan.json") << ": " << total << " tasks\n";
  if (o.estimate_from.empty())
    printNoEstimate(p);
  else
    printEstimate(estimate, o.estimate_from, p.slurm);
  return 0;
}

Subcommand addPlan(CLI::App& app) {
  auto o = std::make_shared<PlanOptions>();
  CLI::App* plan = app.add_subcommand("plan", "Write the shards, the manifest (plan.json) and one sbatch script per stage");
  addExample(*plan, "occsweep cluster plan --out plan --experiment sweep --dataset ds --grid octomap-opt:2");
  plan->add_option("--experiment", o->config.experiment, "reproduce: generate data, sweep, merge, compare; sweep: existing data sets")
      ->check(CLI::IsMember({"reproduce", "sweep"}))->capture_default_str();
  plan->add_option("--out", o->dir, "Plan folder (tasks run there; outputs go under it)")->type_name(kPath)->required();
  addPlanDataOptions(*plan, *o);
  addPlanRunOptions(*plan, *o);
  plan->add_flag("--force", o->force, "Replace occsweep's own different plan.json in --out (nothing else)");
  return {plan, [o] { return runPlan(*o); }};
}

Subcommand addSelect(CLI::App& app) {
  auto t = std::make_shared<SelectTask>();
  CLI::App* select = app.add_subcommand("select", "Task of ranked plans: link a data set's generated sets as pcs-NNNN and rank-N");
  addExample(*select, "occsweep cluster select gen/building-plain-I/ranking.json --out sets");
  addSelectOptions(*select, *t);  // task_options.cpp: also what `cluster plan` tasks are parsed with
  return {select, [t] {
            const auto n = selectRanked({t->rankings.begin(), t->rankings.end()}, t->out);
            std::cout << "wrote " << escapedControlCharacters(t->out) << ": " << n << " ranked point cloud sets\n";
            return 0;
          }};
}

/// `submit`, or `resubmit`: only the shards whose outputs are missing or invalid, and what depends on them.
Subcommand addSubmit(CLI::App& app, bool resubmit) {
  auto dir = std::make_shared<std::string>();
  CLI::App* sub = resubmit ? app.add_subcommand("resubmit", "Submit only the shards whose outputs are missing or "
                                                            "invalid, and what depends on them")
                           : app.add_subcommand("submit", "Submit a plan: one job array per stage, chained with afterok");
  addExample(*sub, resubmit ? "occsweep cluster resubmit splan"
                            : "occsweep cluster plan --out splan --experiment sweep --dataset ds --grid octomap-opt:1\n"
                              "occsweep cluster submit splan\noccsweep cluster status splan --wait --timeout 600");
  sub->add_option("dir", *dir, "Plan folder")->type_name(kPath)->required();
  return {sub, [dir, resubmit] { return (void)submitPlan(readPlan(*dir), *dir, resubmit, std::cout), 0; }};
}

struct StatusOptions {
  std::string dir;
  bool wait = false, all = false, quiet = false;
  double timeout = 0, poll = 2;
};

int runStatus(const StatusOptions& o) {
  const ClusterPlan p = readPlan(o.dir);
  std::size_t live = 0;
  const auto start = std::chrono::steady_clock::now();
  while (o.wait) {
    (void)printStatus(p, o.dir, false, true, &live);
    if (live == 0) break;
    const double waited = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (o.timeout > 0 && waited > o.timeout) {
      std::cerr << "status: still " << live << " tasks running or pending after " << o.timeout << " s\n";
      break;
    }
    if (!o.quiet) std::cerr << "waiting: " << live << " tasks running or pending (" << int(waited) << " s)\n";
    std::this_thread::sleep_for(std::chrono::duration<double>(o.poll));
  }
  return printStatus(p, o.dir, o.all, false, &live) == 0 ? 0 : 1;
}

Subcommand addStatus(CLI::App& app) {
  auto o = std::make_shared<StatusOptions>();
  CLI::App* status = app.add_subcommand("status", "Done, running, pending, failed and missing shards (exit 0: all done)");
  addExample(*status, "occsweep cluster status plan");
  status->add_option("dir", o->dir, "Plan folder")->type_name(kPath)->required();
  status->add_flag("--wait", o->wait, "Wait until no task is running or pending, then print");
  status->add_option("--timeout", o->timeout, "With --wait: give up after this many seconds (0: never)")->capture_default_str();
  status->add_option("--poll", o->poll, "With --wait: seconds between looks")->capture_default_str()->check(numberAbove(0));
  status->add_flag("--list-done", o->all, "List every task, done ones too");
  status->add_flag("--quiet", o->quiet, "With --wait: no progress on stderr while waiting");
  return {status, [o] { return runStatus(*o); }};
}

Subcommand addRunLocal(CLI::App& app) {
  auto dir = std::make_shared<std::string>();
  auto threads = std::make_shared<int>(1);
  auto quiet = std::make_shared<bool>(false);
  CLI::App* local = app.add_subcommand("run-local", "Run the plan's unfinished shards on this machine");
  addExample(*local, "occsweep cluster run-local plan --threads 2");
  local->add_option("dir", *dir, "Plan folder")->type_name(kPath)->required();
  local->add_option("--threads", *threads, "Tasks run at a time (each sweep task uses the plan's --threads)")
      ->capture_default_str()->check(threadCount(1));
  local->add_flag("--quiet", *quiet, "No progress on stderr (failures, warnings and a stop are still printed)");
  return {local, [dir, threads, quiet] {
            const std::size_t failed = runLocal(readPlan(*dir), *dir, *threads, *quiet);
            if (failed) std::cerr << failed << " tasks failed: fix them and run again (done tasks are kept)\n";
            return failed ? 1 : 0;
          }};
}

const RegisterCommand kCluster{"cluster", "Plan, submit and check sharded experiments (Slurm job arrays or local)",
                               [](CLI::App& app) {
  app.require_subcommand(1);
  // Added in the order of the help: plan, select, submit, status, resubmit, run-local.
  const std::vector<Subcommand> subs = {addPlan(app), addSelect(app), addSubmit(app, false), addStatus(app),
                                        addSubmit(app, true), addRunLocal(app)};
  return [subs] { return runChosen(subs); };
}};

}  // namespace
}  // namespace occsweep::cli
