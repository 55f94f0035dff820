// occsweep cluster plan|submit|status|resubmit|run-local: sharded experiments as Slurm job arrays (docs/cluster.md).
#include <chrono>
#include <iostream>
#include <thread>

#include "command_registry.hpp"
#include "option_checks.hpp"
#include "occsweep/sweeps/cluster_select.hpp"
#include "occsweep/sweeps/cluster_slurm.hpp"

namespace occsweep::cli {
namespace {

/// The paper's 20 data sets (docs/definitions.md, The 20 data sets).
std::vector<std::string> paperDatasets() {
  std::vector<std::string> out;
  for (const char* env : {"building", "parking"})
    for (const char* tex : {"plain", "voronoi"})
      for (const char* layout : {"I", "O", "T", "L", "S"}) out.push_back(std::string(env) + "-" + tex + "-" + layout);
  return out;
}

std::string selfPath() {
  std::error_code ec;
  const auto p = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::string("occsweep") : p.string();
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
  return not_done;
}

const RegisterCommand kCluster{"cluster", "Plan, submit and check sharded experiments (Slurm job arrays or local)",
                               [](CLI::App& app) {
  auto c = std::make_shared<PlanConfig>();
  auto dir = std::make_shared<std::string>();
  auto grids = std::make_shared<std::vector<std::string>>();
  auto kind = std::make_shared<std::string>("exists");
  auto replace = std::make_shared<bool>(false);
  auto jobs = std::make_shared<int>(1);
  auto wait = std::make_shared<bool>(false), all = std::make_shared<bool>(false);
  auto timeout = std::make_shared<double>(0), poll = std::make_shared<double>(2);

  CLI::App* plan = app.add_subcommand("plan", "Write the shards, the manifest (plan.json) and one sbatch script per stage");
  plan->add_option("--experiment", c->experiment, "reproduce: generate data, sweep, merge, compare; sweep: existing data sets")
      ->check(CLI::IsMember({"reproduce", "sweep"}))->capture_default_str();
  plan->add_option("--out", *dir, "Plan folder (tasks run there; outputs go under it)")->required();
  plan->add_option("--datasets", c->datasets, "reproduce: data-set names (default the paper's 20); sweep: data-set folders")
      ->delimiter(',');
  plan->add_option("--generate", c->generate, "Generation command, occsweep arguments; {dataset} {index} {seed} {block} {blocks} {out} {scale}")
      ->capture_default_str();
  plan->add_option("--generate-out", c->generate_out, "What one generation task writes, relative to the plan folder")->capture_default_str();
  plan->add_option("--generate-kind", *kind, "How a generation output is checked")
      ->check(CLI::IsMember({"exists", "dataset"}))->capture_default_str();
  plan->add_option("--scale", c->scale, "{scale} of the generation command")->capture_default_str();
  auto* blocks = plan->add_option("--blocks", c->blocks, "Generation shards per data set: blocks of point cloud parameter ids ({pcs})")
      ->capture_default_str()->check(integerAtLeast<std::uint64_t>(1));
  plan->add_option("--pcs-count", c->pcs_count, "Point cloud parameter ids 0..N-1 to generate")->capture_default_str()->check(integerAtLeast<std::uint64_t>(1));
  // Read through count(): no bound variable, which would have to outlive parsing (ASan caught a freed one).
  auto* unranked = plan->add_flag("--unranked")->description("No select stage: sweep folders under the generated "
                                                             "output itself (defaults then: --blocks 1 --sets . --group-set '')");
  auto* sets = plan->add_option("--sets", c->sets, "Point cloud sets to sweep, per data set: rank-N or pcs-NNNN (ranked), or "
                                                   "folders relative to the data set ('.': itself, the default of "
                                                   "--experiment sweep)")
      ->delimiter(',')->capture_default_str();
  auto* group_set = plan->add_option("--group-set", c->group_set, "The set that grouped grids sweep")->capture_default_str();
  plan->add_option("--grids", *grids, "NAME[:SHARDS[:grouped]], grouped: data set i sweeps Eq. 16 group i of the data sets "
                                      "(default octomap-opt:1,knn-opt:4, and reduction:4:grouped for reproduce)")->delimiter(',');
  plan->add_option("--group-seed", c->group_seed, "Eq. 16 permutation seed of grouped grids")->capture_default_str();
  plan->add_option("--threads", c->sweep_threads, "--threads of each sweep (0: --cpus-per-task)")->capture_default_str();
  plan->add_option("--sweep-args", c->sweep_args, "More `occsweep sweep` arguments for every sweep, e.g. --s-c,4")->delimiter(',');
  plan->add_option("--occsweep", c->occsweep, "occsweep binary the tasks run (default: this one)");
  plan->add_option("--cpus-per-task", c->slurm.cpus_per_task, "sbatch --cpus-per-task")->capture_default_str()->check(integerAtLeast<int>(1));
  plan->add_option("--mem", c->slurm.mem, "sbatch --mem")->capture_default_str();
  plan->add_option("--time", c->slurm.time, "sbatch --time")->capture_default_str();
  plan->add_option("--partition", c->slurm.partition, "sbatch --partition");
  plan->add_option("--account", c->slurm.account, "sbatch --account");
  plan->add_option("--sbatch", c->slurm.extra, "More #SBATCH options, verbatim (repeatable), e.g. --qos=long");
  plan->add_flag("--replace", *replace, "Overwrite a different plan.json in --out");

  auto rankings = std::make_shared<std::vector<std::string>>();
  CLI::App* select = app.add_subcommand("select", "Task of ranked plans: link a data set's generated sets as pcs-NNNN and rank-N");
  select->add_option("--out", *dir, "Folder of links to write")->required();
  select->add_option("rankings", *rankings, "ranking.json of every generation block of the data set")->required();
  CLI::App* submit = app.add_subcommand("submit", "Submit a plan: one job array per stage, chained with afterok");
  CLI::App* status = app.add_subcommand("status", "Done, running, pending, failed and missing shards (exit 0: all done)");
  CLI::App* resubmit = app.add_subcommand("resubmit", "Submit only the shards whose outputs are missing or invalid, and what depends on them");
  CLI::App* local = app.add_subcommand("run-local", "Run the plan's unfinished shards on this machine");
  for (CLI::App* sub : {submit, status, resubmit, local}) sub->add_option("dir", *dir, "Plan folder")->required();
  status->add_flag("--wait", *wait, "Wait until no task is running or pending, then print");
  status->add_option("--timeout", *timeout, "With --wait: give up after this many seconds (0: never)")->capture_default_str();
  status->add_option("--poll", *poll, "With --wait: seconds between looks")->capture_default_str()->check(numberAbove(0));
  status->add_flag("--all", *all, "List every task, done ones too");
  local->add_option("-j,--jobs", *jobs, "Tasks at a time")->capture_default_str()->check(integerAtLeast<int>(1));
  app.require_subcommand(1);

  return [=] {
    return runChosen({
        {plan, [=] {
           PlanConfig cfg = *c;
           if (unranked->count()) {
             cfg.ranked = false;
             if (!blocks->count()) cfg.blocks = 1;
             if (!sets->count()) cfg.sets = {"."};
             if (!group_set->count()) cfg.group_set.clear();
           }
           if (cfg.experiment == "sweep") {  // user data-set folders: each one is the set to sweep
             if (!sets->count()) cfg.sets = {"."};
             if (!group_set->count()) cfg.group_set.clear();
           }
           if (cfg.occsweep.empty()) cfg.occsweep = selfPath();
           cfg.occsweep = std::filesystem::absolute(cfg.occsweep).string();
           if (cfg.datasets.empty() && cfg.experiment == "reproduce") cfg.datasets = paperDatasets();
           std::vector<std::string> g = *grids;
           if (g.empty()) g = {"octomap-opt:1", "knn-opt:4"};
           if (grids->empty() && cfg.experiment == "reproduce") g.push_back("reduction:4:grouped");
           cfg.grids.clear();
           for (const auto& text : g) cfg.grids.push_back(parsePlanGrid(text));
           cfg.generate_kind = kindFromName(*kind);
           const ClusterPlan p = buildPlan(cfg);
           writePlan(p, *dir, *replace);
           std::size_t total = 0;
           for (const auto& s : p.stages) {
             std::cout << "stage " << s.name << ": " << s.tasks.size() << " tasks"
                       << (s.after.empty() ? "" : " (after " + s.after[0] + ")") << ", " << *dir << "/slurm/"
                       << s.name << ".sbatch\n";
             total += s.tasks.size();
           }
           std::cout << "wrote " << *dir << "/plan.json: " << total << " tasks\n";
           return 0;
         }},
        {select, [=] {
           const auto n = selectRanked({rankings->begin(), rankings->end()}, *dir);
           std::cout << "wrote " << *dir << ": " << n << " ranked point cloud sets\n";
           return 0;
         }},
        {submit, [=] { return (void)submitPlan(readPlan(*dir), *dir, false, std::cout), 0; }},
        {resubmit, [=] { return (void)submitPlan(readPlan(*dir), *dir, true, std::cout), 0; }},
        {local, [=] {
           const std::size_t failed = runLocal(readPlan(*dir), *dir, *jobs);
           if (failed) std::cerr << failed << " tasks failed: fix them and run again (done tasks are kept)\n";
           return failed ? 1 : 0;
         }},
        {status, [=] {
           const ClusterPlan p = readPlan(*dir);
           std::size_t live = 0;
           const auto start = std::chrono::steady_clock::now();
           while (*wait) {
             (void)printStatus(p, *dir, false, true, &live);
             if (live == 0) break;
             const double waited = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
             if (*timeout > 0 && waited > *timeout) {
               std::cerr << "status: still " << live << " tasks running or pending after " << *timeout << " s\n";
               break;
             }
             std::cerr << "waiting: " << live << " tasks running or pending (" << int(waited) << " s)\n";
             std::this_thread::sleep_for(std::chrono::duration<double>(*poll));
           }
           return printStatus(p, *dir, *all, false, &live) == 0 ? 0 : 1;
         }},
    });
  };
}};

}  // namespace
}  // namespace occsweep::cli
