// A cluster plan: the work of an experiment cut into shards, grouped in stages that run as one Slurm job
// array each, chained with --dependency=afterok. The same plan runs on one machine with `cluster run-local`.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "occsweep/sweeps/cluster_tasks.hpp"

namespace occsweep {

/// How a task's output is judged done (cluster_state.hpp). Every command a plan runs writes its output atomically
/// (temporary name + rename), so a killed task leaves no output that passes these checks.
enum class OutputKind {
  Results,     ///< occsweep results file: complete, consistent, of the expected grid and shard
  Comparison,  ///< `occsweep compare --json` file ("format": "occsweep-comparison")
  Dataset,     ///< data-set folder whose manifest.json parses
  Exists,      ///< any file or folder (custom generation commands)
};

/// The header fields of a results file that a plan fixes besides grid and shard: the sweep settings every task of the
/// plan shares and the task's Eq. 16 group.
struct ExpectedWork {
  std::optional<SweepSelection::Group> group;
  MapSettings map;
  TruthMode truth = TruthMode::Full;
  friend bool operator==(const ExpectedWork&, const ExpectedWork&) = default;
};

/// One shard: one occsweep command, its inputs (outputs of earlier stages) and its output, paths relative to the
/// plan folder (tasks run there).
struct ClusterTask {
  std::uint64_t index = 0;             ///< the array task id
  std::string label;                   ///< what it is, for status ("ds0 knn-opt 2/3")
  std::vector<std::string> argv;       ///< argv[0] is the occsweep binary; the rest taskArgv of a typed task
                                       ///< (cluster_tasks.hpp), or the generation template filled in
  std::vector<std::string> inputs;
  std::string output;
  OutputKind kind = OutputKind::Exists;
  std::string expect_grid;             ///< Results: the grid name the file must have
  std::uint64_t expect_shard = 0, expect_shards = 1;
  /// Results: the work the file must describe beside its grid and shard (its Eq. 16 group and map settings), so
  /// that occsweep's results of other work at the output's name never count as done (docs/cluster.md, "Status").
  /// Plans written before the field have none: only grid and shard are checked.
  std::optional<ExpectedWork> expect_work;
};

struct ClusterStage {
  std::string name;                    ///< generate, sweep, merge, report
  std::vector<std::string> after;      ///< stages whose arrays must succeed first (afterok)
  std::vector<ClusterTask> tasks;
};

/// The largest --array-throttle and --max-array-size (Slurm's own MaxArraySize limit is 4,000,001).
inline constexpr std::uint64_t kMaxArrayThrottle = 1'000'000, kMaxArraySizeLimit = 4'000'001;

/// sbatch options of every stage's script (docs/cluster.md, "A plan a real cluster runs"). Empty strings are left
/// out.
struct SlurmOptions {
  int cpus_per_task = 1;
  std::string mem = "1G", time = "01:00:00", partition, account;
  std::vector<std::string> extra;      ///< more `#SBATCH` options, verbatim (e.g. --qos=normal)
  std::map<std::string, std::string> stage_mem, stage_time;  ///< per stage name, over `mem` and `time`
  std::vector<std::string> setup;      ///< shell lines every task runs first (`module load ...`, a virtualenv)
  std::uint64_t array_throttle = 0;    ///< at most this many tasks of an array at once (`--array=...%N`); 0: no limit
  std::uint64_t max_array_size = 0;    ///< Slurm's MaxArraySize; 0: read from `scontrol show config` at submit
};
/// The name of the file system holding `path` when it is one that is local to a machine (ext4, xfs, btrfs, tmpfs,
/// overlay, zfs): compute nodes would not see a binary or a plan folder there. Nothing for network and cluster file
/// systems (NFS, Lustre, GPFS, BeeGFS, CephFS, ...) and for any it does not know.
[[nodiscard]] std::optional<std::string> localFileSystemOf(const std::filesystem::path& path);
/// A stage's --mem and --time: its own when given, else every stage's.
[[nodiscard]] std::string stageMem(const SlurmOptions& o, const std::string& stage);
[[nodiscard]] std::string stageTime(const SlurmOptions& o, const std::string& stage);
/// `--mem`/`--time` as given on the command line, VALUE for every stage or STAGE=VALUE for one (repeatable), into
/// `every` and `per_stage`; std::invalid_argument naming `flag` for an empty value or a stage given twice.
void parseStageValues(const std::vector<std::string>& given, const std::string& flag, std::string& every,
                      std::map<std::string, std::string>& per_stage);

struct ClusterPlan {
  std::string experiment;              ///< reproduce | sweep
  std::string occsweep;                ///< absolute path of the occsweep binary the tasks run
  SlurmOptions slurm;
  std::vector<ClusterStage> stages;    ///< in dependency order
};

/// The sbatch settings of a plan, built or read back: a --mem, --time, --partition or --account value is one word (it
/// becomes an `#SBATCH` line), a set-up line or an --sbatch option one line, and a stage named in `--mem STAGE=...`
/// or `--time STAGE=...` one of the plan's; std::invalid_argument naming the flag and the rule.
void checkSlurmOptions(const ClusterPlan& plan);

/// One grid of a plan: NAME[:SHARDS[:grouped]]. Grouped: data set i of n sweeps only Eq. 16 group i/n.
struct PlanGrid {
  std::string name;
  std::uint64_t shards = 1;
  bool grouped = false;
};

/// The most point cloud parameter ids `--pcs-count` may ask for (the paper's grid has 1,600): every id is written
/// into a generation task's command line and plan.json, so the plan grows with it (docs/cluster.md, "Options").
inline constexpr std::uint64_t kMaxPcsCount = 100'000;
/// The longest {pcs} one generation task may get: Linux's limit on one command-line argument (MAX_ARG_STRLEN,
/// 32 pages), past which the task could not even start.
inline constexpr std::size_t kMaxPcsArgumentBytes = 131'072 - 1;

/// What `cluster plan` was asked for; applyPlanDefaults fills what the experiment decides (docs/cluster.md). Generation templates
/// take {dataset} {index} {seed} {block} {blocks} {block_dir} {pcs} {cpus} {scale} {out}.
struct PlanConfig {
  std::string experiment = "reproduce";
  std::string occsweep;                     ///< binary; default: the running one
  std::vector<std::string> datasets;        ///< reproduce: names; sweep: existing data-set folders
  std::string generate =
      "dataset generate --name {dataset} --out {block_dir} --scale {scale} --pcs {pcs} --threads {cpus} --no-preview "
      "--force";
  std::string generate_out = "{block_dir}/{dataset}/ranking.json";  ///< what one generation task writes last
  OutputKind generate_kind = OutputKind::Exists;
  std::string scale = "paper";
  std::uint64_t blocks = 16;                ///< generation shards per data set: blocks of point cloud parameter ids
  std::uint64_t pcs_count = 1600;           ///< point cloud parameter ids 0..pcs_count-1, cut into `blocks` ({pcs})
  bool ranked = true;                       ///< a select stage links every block's sets as pcs-NNNN and rank-N
  std::vector<std::string> sets = {"rank-1", "rank-800", "rank-1600"};  ///< sets to sweep (paper 4.3)
  std::string group_set = "rank-800";       ///< the one set grouped grids sweep (empty: the first of `sets`)
  std::vector<PlanGrid> grids = {{"octomap-opt", 1, false}, {"knn-opt", 4, false}};
  std::uint64_t group_seed = 0;             ///< Eq. 16 permutation seed of grouped grids
  int sweep_threads = 0;                    ///< --threads of each sweep (0: --cpus-per-task)
  /// What every sweep shares (resolution, s_c, variant, stats, engine, truth, quiet): `--sweep-args`. Each task
  /// sets its own dataset, grid, out, selection and threads.
  SweepConfig sweep;
  SlurmOptions slurm;
};

/// Which of the settings applyPlanDefaults decides the user gave (`cluster plan` options).
struct PlanChoices {
  bool datasets = false, grids = false, sets = false, group_set = false, blocks = false;
};
/// The defaults that depend on the experiment, for each setting not given: reproduce plans the paper's 20 data sets
/// (paperDatasetNames) and adds the grouped reduction grid (reduction:4:grouped) to octomap-opt:1 and knn-opt:4;
/// unranked plans (ranked false) generate one block; sweep and unranked plans sweep each folder itself ('.') with no
/// group set.
void applyPlanDefaults(PlanConfig& c, const PlanChoices& given);

/// "knn-opt:4", "reduction:8:grouped"; std::invalid_argument naming the text otherwise.
[[nodiscard]] PlanGrid parsePlanGrid(const std::string& text);
/// Fills every {key} of `text` from `values`; std::invalid_argument for an unknown key or an unclosed brace.
[[nodiscard]] std::string expandTemplate(const std::string& text, const std::map<std::string, std::string>& values);
/// Splits a command template on spaces (no quoting: a template is a plain argument list).
[[nodiscard]] std::vector<std::string> splitArgs(const std::string& text);

/// The stages of an experiment: [generate ->] sweep -> merge -> report. Throws std::invalid_argument for an
/// inconsistent configuration (no data sets, zero shards, a grid name given twice).
[[nodiscard]] ClusterPlan buildPlan(const PlanConfig& config);

/// The rule a task's output path breaks, or none: it must be relative and inside the plan folder (no `..`), since
/// run-local and resubmit write and remove it (docs/cluster.md, "Outputs stay in the plan folder").
[[nodiscard]] std::optional<std::string> brokenPlanOutputRule(const std::string& output);

/// Writes DIR/plan.json (the manifest) and DIR/slurm/<stage>.sbatch, each file atomically. A plan.json already in
/// DIR that is not occsweep's own plan (its `format` field) is refused, even with `force`, changing nothing; a
/// different occsweep plan is replaced only with `force` (the --force of every command). std::invalid_argument
/// for a task output that breaks brokenPlanOutputRule.
void writePlan(const ClusterPlan& plan, const std::filesystem::path& dir, bool force);
/// Reads DIR/plan.json; std::runtime_error naming the file and field for anything malformed.
[[nodiscard]] ClusterPlan readPlan(const std::filesystem::path& dir);

/// The sbatch script of one stage: a bash `case` on the task, SLURM_ARRAY_TASK_ID + OCCSWEEP_TASK_OFFSET, one occsweep
/// command per task.
[[nodiscard]] std::string sbatchScript(const ClusterPlan& plan, const ClusterStage& stage);
/// The script an occsweep before array offsets wrote for the stage (one --mem and --time, no set-up lines, the task the
/// array index): occsweep's own when its plan is written again, which replaces it; never submitted.
[[nodiscard]] std::string sbatchScriptBeforeOffsets(const ClusterPlan& plan, const ClusterStage& stage);
/// The stage's task list; std::out_of_range for an unknown stage.
[[nodiscard]] const ClusterStage& stageNamed(const ClusterPlan& plan, const std::string& name);

[[nodiscard]] const char* kindName(OutputKind k);
[[nodiscard]] OutputKind kindFromName(const std::string& name);  ///< std::invalid_argument otherwise

}  // namespace occsweep
