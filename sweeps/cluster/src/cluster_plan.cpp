// Building a cluster plan: which shards an experiment needs, their commands, inputs and outputs.
#include <algorithm>
#include <map>
#include <set>
#include <stdexcept>
#include <tuple>

#include "occsweep/sweeps/cluster_plan.hpp"
#include "occsweep/core/limits.hpp"
#include "occsweep/sweeps/grid.hpp"
#include "occsweep/eval/paper_datasets.hpp"
#include "occsweep/sweeps/sharding.hpp"

namespace occsweep {
namespace {

/// One point cloud set to sweep: its folder (relative to the plan folder, or absolute) and a key for file names.
struct SweptSet {
  std::string dir, key, set;
  std::size_t dataset_index = 0;
  std::vector<std::string> generated;  ///< outputs of its data set's generation (or select) tasks
};

// A data-set or set name made one harmless path component (brokenPathComponentRule): it names output folders.
std::string fileKey(std::string text) {
  for (char& c : text)
    if (c == '/' || c == '\\' || c == ' ' || c == ':' || static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '_';
  if (!text.empty() && text.front() == '.') text.front() = '_';
  return text;
}

std::string joinPath(const std::string& dir, const std::string& set) {
  return set == "." ? dir : (std::filesystem::path(dir) / set).lexically_normal().string();
}

/// Data-set keys must be unique: they name output folders.
std::vector<std::string> datasetKeys(const PlanConfig& c) {
  std::vector<std::string> keys;
  std::set<std::string> seen;
  for (std::size_t i = 0; i < c.datasets.size(); ++i) {
    std::string key = c.experiment == "sweep" ? std::filesystem::path(c.datasets[i]).lexically_normal().filename().string()
                                              : c.datasets[i];
    if (key.empty() || key == "." || key == "..") key = "dataset";
    key = fileKey(key);
    if (!seen.insert(key).second) (key += '-') += std::to_string(i);  // not "-" + ...: GCC 12 -Wrestrict false positive
    seen.insert(key);
    keys.push_back(key);
  }
  return keys;
}

/// Generation of data set i, block b: the template filled in.
ClusterTask generationTask(const PlanConfig& c, std::size_t i, const std::string& key, std::uint64_t b) {
  const Block ids = contiguousBlock(c.pcs_count, c.blocks, b);
  if (ids.begin == ids.end)
    throw std::invalid_argument("--blocks " + std::to_string(c.blocks) + " is more than --pcs-count " +
                                std::to_string(c.pcs_count) + ": empty blocks");
  std::string pcs;
  for (auto id = ids.begin; id < ids.end; ++id) {
    if (!pcs.empty()) pcs += ',';
    pcs += std::to_string(id);
    if (pcs.size() > kMaxPcsArgumentBytes && c.generate.find("{pcs}") != std::string::npos)
      throw std::invalid_argument("--pcs-count " + std::to_string(c.pcs_count) + " in --blocks " +
                                  std::to_string(c.blocks) + ": one block's {pcs} ids pass " +
                                  std::to_string(kMaxPcsArgumentBytes) + " bytes, the longest argument a command "
                                  "line may hold; raise --blocks");
  }
  std::map<std::string, std::string> v = {
      {"dataset", c.datasets[i]}, {"index", std::to_string(i)}, {"seed", std::to_string(i + 1)},
      {"block", std::to_string(b)}, {"blocks", std::to_string(c.blocks)}, {"scale", c.scale}, {"pcs", pcs},
      {"cpus", std::to_string(c.slurm.cpus_per_task)}, {"block_dir", "data/" + key + "/block-" + std::to_string(b)}};
  v["out"] = expandTemplate(c.generate_out, v);
  ClusterTask t;
  t.label = key + (c.blocks > 1 ? " block " + std::to_string(b) + "/" + std::to_string(c.blocks) : "");
  t.argv = {c.occsweep};
  for (auto& a : splitArgs(expandTemplate(c.generate, v))) t.argv.push_back(a);
  t.output = v["out"];
  t.kind = c.generate_kind;
  return t;
}

std::vector<std::string> withProgram(const std::string& program, std::vector<std::string> args) {
  args.insert(args.begin(), program);
  return args;
}

/// The set whose sweeps take the Eq. 16 groups of grouped grids: --group-set, else the first of --sets.
std::string groupSet(const PlanConfig& c) { return c.group_set.empty() ? c.sets[0] : c.group_set; }

void checkPlanConfig(const PlanConfig& c) {
  if (c.experiment != "reproduce" && c.experiment != "sweep")
    throw std::invalid_argument("--experiment '" + c.experiment + "': expected reproduce or sweep");
  if (c.datasets.empty()) throw std::invalid_argument("no data sets: give --dataset (--experiment sweep) or --name");
  if (c.grids.empty()) throw std::invalid_argument("no grids: give --grid");
  if (c.blocks == 0) throw std::invalid_argument("--blocks must be at least 1");
  if (c.pcs_count > kMaxPcsCount)
    throw std::invalid_argument("--pcs-count " + std::to_string(c.pcs_count) + " is more than the limit of " +
                                std::to_string(kMaxPcsCount) + " point cloud parameter ids (each id is written into "
                                "a generation task's command line and plan.json; docs/cluster.md)");
  if (c.sets.empty()) throw std::invalid_argument("--sets must name at least one point cloud set");
  if (c.experiment == "reproduce" && c.blocks > 1 && !c.ranked)
    throw std::invalid_argument("--blocks > 1 needs the select stage to gather the blocks' sets (drop --unranked)");
  const std::string group_set = groupSet(c);
  if (std::find(c.sets.begin(), c.sets.end(), group_set) == c.sets.end())
    for (const auto& g : c.grids)
      if (g.grouped) throw std::invalid_argument("--group-set " + group_set + " is not one of --sets");
}

/// The sets of `c.sets` in data set i's folder `dir`; their sweeps wait for `deps`.
/// Two sets whose names make one key (`x/y` and `x_y` both `x_y`) would share their outputs, and one of them would
/// never be swept: refused, naming both.
void addSweptSets(const PlanConfig& c, std::size_t i, const std::string& key, const std::string& dir,
                  const std::vector<std::string>& deps, std::vector<SweptSet>& swept) {
  std::map<std::string, std::string> set_of_key;
  for (const auto& s : c.sets) {
    const std::string set_key = key + (s == "." ? "" : "/" + fileKey(s));
    if (const auto [it, fresh] = set_of_key.emplace(set_key, s); !fresh)
      throw std::invalid_argument("--sets " + it->second + " and " + s + " would share the plan's outputs (both "
                                  "named " + set_key + "): give each set once, under names that differ in more "
                                  "than '/' and '_'");
    swept.push_back({joinPath(dir, s), set_key, s, i, deps});
  }
}

/// The select task of a ranked plan: the data set's blocks linked as pcs-NNNN and rank-N in one folder.
ClusterTask selectTask(const PlanConfig& c, const std::string& key, const std::vector<std::string>& generated) {
  ClusterTask t;
  t.label = key;
  t.output = "data/" + key + "/sets";
  t.argv = withProgram(c.occsweep, taskArgv(SelectTask{generated, t.output}));
  t.inputs = generated;
  return t;
}

/// reproduce: the generate stage (and select, when ranked); returns the sets to sweep.
std::vector<SweptSet> addGenerationStages(const PlanConfig& c, const std::vector<std::string>& keys,
                                          ClusterPlan& plan) {
  ClusterStage gen{"generate", {}, {}}, select{"select", {"generate"}, {}};
  std::vector<SweptSet> swept;
  for (std::size_t i = 0; i < c.datasets.size(); ++i) {
    std::vector<std::string> outputs;
    for (std::uint64_t b = 0; b < c.blocks; ++b) {
      ClusterTask t = generationTask(c, i, keys[i], b);
      t.index = gen.tasks.size();
      outputs.push_back(t.output);
      gen.tasks.push_back(std::move(t));
    }
    // Unranked: sets are folders under the generated output, or under its folder when it is a file (ranking.json).
    std::string dir = outputs[0];
    if (std::filesystem::path(dir).extension() == ".json") dir = std::filesystem::path(dir).parent_path().string();
    std::vector<std::string> deps = outputs;
    if (c.ranked) {
      ClusterTask t = selectTask(c, keys[i], outputs);
      t.index = select.tasks.size();
      dir = t.output;
      deps = {t.output};
      select.tasks.push_back(std::move(t));
    }
    addSweptSets(c, i, keys[i], dir, deps, swept);
  }
  plan.stages.push_back(std::move(gen));
  if (c.ranked) plan.stages.push_back(std::move(select));
  return swept;
}

/// sweep: the sets of the user's data-set folders, named absolutely (tasks run in the plan folder).
std::vector<SweptSet> existingSets(const PlanConfig& c, const std::vector<std::string>& keys) {
  std::vector<SweptSet> swept;
  for (std::size_t i = 0; i < c.datasets.size(); ++i)
    addSweptSets(c, i, keys[i], std::filesystem::absolute(c.datasets[i]).lexically_normal().string(), {}, swept);
  return swept;
}

/// A grid of the plan, loaded: its name in the grid file and how the tasks name it.
struct LoadedGrid {
  PlanGrid plan;
  std::string name, arg;
};

/// The plan's sweep shards and merges are JSON results files, which `sweep` refuses past kMaxJsonCombinations; the
/// merge of an ungrouped grid holds all of it: refused now, not hours later on the cluster.
void refuseLargeJsonGrid(const PlanGrid& g, std::uint64_t combinations) {
  if (g.grouped || combinations <= kMaxJsonCombinations) return;
  throw std::invalid_argument("grid " + g.name + ": " + std::to_string(combinations) + " combinations, more than " +
                              "the " + std::to_string(kMaxJsonCombinations) + " a JSON results file holds (the " +
                              "plan's shards and merges are JSON): sweep it with `occsweep sweep --out NAME.db`");
}

/// Grids are loaded now so that a wrong name or too many shards fail at planning, not on the cluster.
std::vector<LoadedGrid> loadPlanGrids(const PlanConfig& c) {
  std::set<std::string> seen;
  std::map<std::string, std::string> ungrouped_of_method;  // the report compares one result per method and set
  std::vector<LoadedGrid> out;
  for (const auto& g : c.grids) {
    if (g.shards == 0) throw std::invalid_argument("grid " + g.name + ": shards must be at least 1");
    const GridSpec spec = loadGrid(resolveGridPath(g.name));
    if (!seen.insert(spec.name).second) throw std::invalid_argument("grid " + spec.name + " given twice");
    if (const auto [it, fresh] = g.grouped ? std::pair{ungrouped_of_method.end(), true}
                                           : ungrouped_of_method.try_emplace(spec.method, spec.name);
        !fresh)
      throw std::invalid_argument("grids " + it->second + " and " + spec.name + " are both of method " + spec.method +
                                  ": the report compares one result per method and data set (docs/cluster.md); "
                                  "plan them in two plans, or group one of them");
    // Counted, not enumerated (docs/grids.md, "Counting"); a group's task enumerates the whole grid (Eq. 16).
    const std::uint64_t combinations = combinationCount(spec), maps = thresholdedMapCount(spec);
    if (g.grouped)
      checkLimit("grid " + spec.name + ": combinations", combinations, limits().combinations, "--max-combinations");
    if (!g.grouped && g.shards > maps)
      throw std::invalid_argument("grid " + g.name + ": " + std::to_string(g.shards) + " shards but only " +
                                  std::to_string(maps) + " maps (a shard is a block of whole maps)");
    refuseLargeJsonGrid(g, combinations);
    // A grid file named relative to here would not be found by the tasks, which run in the plan folder.
    const std::string arg = std::filesystem::is_regular_file(g.name)
                                ? std::filesystem::absolute(g.name).lexically_normal().string()
                                : g.name;
    out.push_back({g, spec.name, arg});
  }
  return out;
}

/// What a results file of this sweep says besides grid and shard: checked before a task counts as done.
ExpectedWork expectedWork(const SweepConfig& sweep) {
  return {sweep.selection.group, sweep.map, sweep.truth};
}

/// Shard k of grid g on set s: the plan's shared sweep settings with this task's data set, grid, output, shard
/// (and Eq. 16 group when grouped).
ClusterTask sweepTask(const PlanConfig& c, const SweptSet& s, const LoadedGrid& g, std::uint64_t k) {
  const std::uint64_t shards = g.plan.shards;
  ClusterTask t;
  t.label = s.key + " " + g.name + " " + std::to_string(k) + "/" + std::to_string(shards);
  t.output = "sweeps/" + s.key + "/" + g.name + "/shard-" + std::to_string(k) + "-of-" + std::to_string(shards) +
             ".json";
  SweepConfig sweep = c.sweep;
  sweep.dataset = s.dir;
  sweep.grid = g.arg;
  sweep.out = t.output;
  sweep.selection = {};
  sweep.selection.shard_index = k, sweep.selection.shard_count = shards;
  if (g.plan.grouped) sweep.selection.group = SweepSelection::Group{s.dataset_index, c.datasets.size(), c.group_seed};
  sweep.threads = c.sweep_threads > 0 ? c.sweep_threads : c.slurm.cpus_per_task;
  t.argv = withProgram(c.occsweep, taskArgv(sweep));
  t.inputs = s.generated;
  t.kind = OutputKind::Results;
  t.expect_grid = g.name;
  t.expect_shard = k;
  t.expect_shards = shards;
  t.expect_work = expectedWork(sweep);
  return t;
}

/// The merge of the shards `shards` of grid g on set s.
ClusterTask mergeTask(const PlanConfig& c, const SweptSet& s, const LoadedGrid& g,
                      const std::vector<std::string>& shards, const ExpectedWork& work) {
  ClusterTask m;
  m.label = s.key + " " + g.name;
  m.output = "merged/" + s.key + "/" + g.name + ".json";
  // --force: a re-run merge replaces its own earlier result (never another file).
  m.argv = withProgram(c.occsweep, taskArgv(MergeTask{shards, m.output, true}));
  m.inputs = shards;
  m.kind = OutputKind::Results;
  m.expect_grid = g.name;
  m.expect_work = work;
  return m;
}

/// The report: the comparison of the merged optimisation grids (grouped reduction results answer another question),
/// or of every merged file when all grids are grouped.
ClusterTask compareTask(const PlanConfig& c, const std::vector<std::string>& optimisation,
                        const std::vector<std::string>& all_merged) {
  ClusterTask t;
  t.label = "compare";
  t.output = "report/comparison.json";
  t.inputs = optimisation.empty() ? all_merged : optimisation;
  // --force: a re-run replaces its own earlier comparison (never another file).
  CompareTask compare;
  compare.files = t.inputs, compare.json = t.output, compare.force = true;
  t.argv = withProgram(c.occsweep, taskArgv(compare));
  t.kind = OutputKind::Comparison;
  return t;
}

/// sweep -> merge -> report, after the generation stages (reproduce).
void addSweepStages(const PlanConfig& c, const std::vector<SweptSet>& swept, const std::vector<LoadedGrid>& grids,
                    ClusterPlan& plan) {
  ClusterStage sweep{"sweep", {}, {}}, merge{"merge", {"sweep"}, {}}, report{"report", {"merge"}, {}};
  if (c.experiment == "reproduce") sweep.after = {c.ranked ? "select" : "generate"};
  const std::string group_set = groupSet(c);
  std::vector<std::string> optimisation, all_merged;
  for (const auto& s : swept)
    for (const auto& g : grids) {
      if (g.plan.grouped && s.set != group_set) continue;  // Eq. 16 groups go to data sets, one set each
      std::vector<std::string> shards;
      for (std::uint64_t k = 0; k < g.plan.shards; ++k) {
        ClusterTask t = sweepTask(c, s, g, k);
        t.index = sweep.tasks.size();
        shards.push_back(t.output);
        sweep.tasks.push_back(std::move(t));
      }
      // The merge holds what its shards hold: their group and settings.
      ClusterTask m = mergeTask(c, s, g, shards, *sweep.tasks.back().expect_work);
      m.index = merge.tasks.size();
      all_merged.push_back(m.output);
      if (!g.plan.grouped) optimisation.push_back(m.output);
      merge.tasks.push_back(std::move(m));
    }
  report.tasks.push_back(compareTask(c, optimisation, all_merged));
  plan.stages.push_back(std::move(sweep));
  plan.stages.push_back(std::move(merge));
  plan.stages.push_back(std::move(report));
}

}  // namespace

void checkSlurmOptions(const ClusterPlan& plan) {
  const SlurmOptions& o = plan.slurm;
  std::string stages;
  for (const ClusterStage& st : plan.stages) stages += (stages.empty() ? "" : ", ") + st.name;
  const auto oneWord = [](const std::string& flag, const std::string& value) {
    if (value.find_first_of(" \t\r\n\v\f") != std::string::npos)
      throw std::invalid_argument(flag + " '" + value + "': a value may not hold spaces or line breaks (it is one "
                                  "#SBATCH option)");
  };
  for (const auto& [flag, every, per_stage] : {std::tuple{"--mem", &o.mem, &o.stage_mem},
                                               std::tuple{"--time", &o.time, &o.stage_time}}) {
    oneWord(flag, *every);
    for (const auto& entry : *per_stage) {
      const std::string &stage = entry.first, &value = entry.second;  // named: clang 14 captures no binding
      oneWord(flag, value);
      const bool known = std::any_of(plan.stages.begin(), plan.stages.end(), [&](const ClusterStage& st) {
        return st.name == stage;
      });
      if (!known)
        throw std::invalid_argument(std::string(flag) + " " + stage + "=" + value + ": the plan has no stage '" + stage +
                                    "' (its stages: " + stages + ")");
    }
  }
  oneWord("--partition", o.partition);
  oneWord("--account", o.account);
  const auto oneLine = [](const std::string& flag, const std::string& text, const std::string& advice) {
    if (text.find_first_of("\r\n\v\f") != std::string::npos)
      throw std::invalid_argument(flag + " '" + text + "': " + advice);
  };
  for (const std::string& line : o.setup) {
    oneLine("--setup", line, "one line each; give --setup once per line");
    if (!line.empty() && line.back() == '\\')
      throw std::invalid_argument("--setup '" + line + "': ends with a backslash, which would join the script's next "
                                  "line to it");
  }
  if (o.array_throttle > kMaxArrayThrottle)
    throw std::invalid_argument("--array-throttle " + std::to_string(o.array_throttle) + ": at most " +
                                std::to_string(kMaxArrayThrottle));
  if (o.max_array_size > kMaxArraySizeLimit)
    throw std::invalid_argument("--max-array-size " + std::to_string(o.max_array_size) + ": at most " +
                                std::to_string(kMaxArraySizeLimit) + " (Slurm's own limit)");
  for (const std::string& option : o.extra) oneLine("--sbatch", option, "one #SBATCH option each, without a line break");
}

ClusterPlan buildPlan(const PlanConfig& c) {
  checkPlanConfig(c);
  ClusterPlan plan{c.experiment, c.occsweep, c.slurm, {}};
  const auto keys = datasetKeys(c);
  const std::vector<SweptSet> swept = c.experiment == "reproduce" ? addGenerationStages(c, keys, plan)
                                                                  : existingSets(c, keys);
  addSweepStages(c, swept, loadPlanGrids(c), plan);
  checkSlurmOptions(plan);
  return plan;
}

void applyPlanDefaults(PlanConfig& c, const PlanChoices& given) {
  const bool reproduce = c.experiment == "reproduce";
  // Unranked plans and user data-set folders: each generated output or folder is itself the one set to sweep.
  if (!c.ranked && !given.blocks) c.blocks = 1;
  if (!c.ranked || !reproduce) {
    if (!given.sets) c.sets = {"."};
    if (!given.group_set) c.group_set.clear();
  }
  if (reproduce && !given.datasets) c.datasets = paperDatasetNames();
  if (!given.grids) {
    c.grids = PlanConfig{}.grids;
    if (reproduce) c.grids.push_back({"reduction", 4, true});  // Fig. 4's NCA weights: Eq. 16 group per data set
  }
}

}  // namespace occsweep
