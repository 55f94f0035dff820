// Building a cluster plan: which shards an experiment needs, their commands, inputs and outputs.
#include <algorithm>
#include <set>
#include <stdexcept>

#include "occsweep/sweeps/cluster_plan.hpp"
#include "occsweep/sweeps/grid.hpp"
#include "occsweep/sweeps/sharding.hpp"

namespace occsweep {
namespace {

/// One point cloud set to sweep: its folder (relative to the plan folder, or absolute) and a key for file names.
struct SweptSet {
  std::string dir, key, set;
  std::size_t dataset_index = 0;
  std::vector<std::string> generated;  ///< outputs of its data set's generation (or select) tasks
};

std::string fileKey(std::string text) {
  for (char& c : text)
    if (c == '/' || c == ' ' || c == ':') c = '_';
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

}  // namespace

ClusterPlan buildPlan(const PlanConfig& c) {
  if (c.experiment != "reproduce" && c.experiment != "sweep")
    throw std::invalid_argument("--experiment '" + c.experiment + "': expected reproduce or sweep");
  if (c.datasets.empty()) throw std::invalid_argument("no data sets: give --datasets");
  if (c.grids.empty()) throw std::invalid_argument("no grids: give --grids");
  if (c.blocks == 0) throw std::invalid_argument("--blocks must be at least 1");
  if (c.sets.empty()) throw std::invalid_argument("--sets must name at least one point cloud set");
  ClusterPlan plan{c.experiment, c.occsweep, c.slurm, {}};
  const std::string bin = c.occsweep;
  const auto keys = datasetKeys(c);

  std::vector<SweptSet> swept;
  if (c.experiment == "reproduce") {
    if (c.blocks > 1 && !c.ranked)
      throw std::invalid_argument("--blocks > 1 needs the select stage to gather the blocks' sets (drop --unranked)");
    ClusterStage gen{"generate", {}, {}}, select{"select", {"generate"}, {}};
    for (std::size_t i = 0; i < c.datasets.size(); ++i) {
      std::vector<std::string> outputs;
      for (std::uint64_t b = 0; b < c.blocks; ++b) {
        ClusterTask t = generationTask(c, i, keys[i], b);
        t.index = gen.tasks.size();
        outputs.push_back(t.output);
        gen.tasks.push_back(std::move(t));
      }
      // Unranked: sets are folders under the generated output, or under its folder when it is a file
      // (ranking.json).
      std::string dir = outputs[0];
      if (std::filesystem::path(dir).extension() == ".json") dir = std::filesystem::path(dir).parent_path().string();
      std::vector<std::string> deps = outputs;
      if (c.ranked) {
        ClusterTask t;
        t.index = select.tasks.size();
        t.label = keys[i];
        t.output = "data/" + keys[i] + "/sets";
        t.argv = {bin, "cluster", "select", "--out", t.output};
        for (const auto& o : outputs) t.argv.push_back(o);
        t.inputs = outputs;
        dir = t.output;
        deps = {t.output};
        select.tasks.push_back(std::move(t));
      }
      for (const auto& s : c.sets)
        swept.push_back({joinPath(dir, s), keys[i] + (s == "." ? "" : "/" + fileKey(s)), s, i, deps});
    }
    plan.stages.push_back(std::move(gen));
    if (c.ranked) plan.stages.push_back(std::move(select));
  } else {
    for (std::size_t i = 0; i < c.datasets.size(); ++i)
      for (const auto& s : c.sets) {
        const auto dir = std::filesystem::absolute(c.datasets[i]).lexically_normal().string();
        swept.push_back({joinPath(dir, s), keys[i] + (s == "." ? "" : "/" + fileKey(s)), s, i, {}});
      }
  }
  const std::string group_set = c.group_set.empty() ? c.sets[0] : c.group_set;
  if (std::find(c.sets.begin(), c.sets.end(), group_set) == c.sets.end())
    for (const auto& g : c.grids)
      if (g.grouped) throw std::invalid_argument("--group-set " + group_set + " is not one of --sets");

  // Grids are loaded now so that a wrong name or too many shards fail at planning, not on the cluster.
  std::set<std::string> grid_names;
  std::vector<std::string> names, grid_args;
  for (const auto& g : c.grids) {
    if (g.shards == 0) throw std::invalid_argument("grid " + g.name + ": shards must be at least 1");
    const GridSpec spec = loadGrid(resolveGridPath(g.name));
    // A grid file named relative to here would not be found by the tasks, which run in the plan folder.
    grid_args.push_back(std::filesystem::is_regular_file(g.name)
                            ? std::filesystem::absolute(g.name).lexically_normal().string()
                            : g.name);
    if (!grid_names.insert(spec.name).second) throw std::invalid_argument("grid " + spec.name + " given twice");
    const auto maps = enumerateGrid(spec).maps.size();
    if (!g.grouped && g.shards > maps)
      throw std::invalid_argument("grid " + g.name + ": " + std::to_string(g.shards) + " shards but only " +
                                  std::to_string(maps) + " maps (a shard is a block of whole maps)");
    names.push_back(spec.name);
  }

  ClusterStage sweep{"sweep", {}, {}}, merge{"merge", {"sweep"}, {}}, report{"report", {"merge"}, {}};
  if (c.experiment == "reproduce") sweep.after = {c.ranked ? "select" : "generate"};
  ClusterTask compare;
  compare.argv = {bin, "compare"};
  compare.label = "compare";
  std::vector<std::string> all_merged;
  const int threads = c.sweep_threads > 0 ? c.sweep_threads : c.slurm.cpus_per_task;
  for (const auto& s : swept) {
    for (std::size_t gi = 0; gi < c.grids.size(); ++gi) {
      const PlanGrid& g = c.grids[gi];
      if (g.grouped && s.set != group_set) continue;  // Eq. 16 groups go to data sets, one set each
      ClusterTask m;
      m.index = merge.tasks.size();
      m.label = s.key + " " + names[gi];
      m.argv = {bin, "merge"};
      for (std::uint64_t k = 0; k < g.shards; ++k) {
        ClusterTask t;
        t.index = sweep.tasks.size();
        t.label = s.key + " " + names[gi] + " " + std::to_string(k) + "/" + std::to_string(g.shards);
        t.output = "sweeps/" + s.key + "/" + names[gi] + "/shard-" + std::to_string(k) + "-of-" +
                   std::to_string(g.shards) + ".json";
        t.argv = {bin, "sweep", "--dataset", s.dir, "--grid", grid_args[gi], "--out", t.output,
                  "--shard", std::to_string(k) + "/" + std::to_string(g.shards), "--threads", std::to_string(threads)};
        if (g.grouped)
          for (auto a : {std::string("--group"), std::to_string(s.dataset_index) + "/" + std::to_string(c.datasets.size()),
                         std::string("--seed"), std::to_string(c.group_seed)})
            t.argv.push_back(a);
        for (const auto& a : c.sweep_args) t.argv.push_back(a);
        t.inputs = s.generated;
        t.kind = OutputKind::Results;
        t.expect_grid = names[gi];
        t.expect_shard = k;
        t.expect_shards = g.shards;
        m.argv.push_back(t.output);
        m.inputs.push_back(t.output);
        sweep.tasks.push_back(std::move(t));
      }
      m.output = "merged/" + s.key + "/" + names[gi] + ".json";
      m.argv.push_back("--out");
      m.argv.push_back(m.output);
      m.argv.push_back("--force");  // a re-run merge replaces its own earlier result (never another file)
      m.kind = OutputKind::Results;
      m.expect_grid = names[gi];
      all_merged.push_back(m.output);
      // The report compares the optimisation grids; grouped (reduction) results answer another question.
      if (!g.grouped) {
        compare.argv.push_back(m.output);
        compare.inputs.push_back(m.output);
      }
      merge.tasks.push_back(std::move(m));
    }
  }
  if (compare.inputs.empty())
    for (const auto& f : all_merged) {
      compare.argv.push_back(f);
      compare.inputs.push_back(f);
    }
  compare.output = "report/comparison.json";
  compare.argv.push_back("--force");  // a re-run replaces its own earlier comparison (never another file)
  compare.argv.push_back("--json");
  compare.argv.push_back(compare.output);
  compare.kind = OutputKind::Comparison;
  report.tasks.push_back(std::move(compare));
  plan.stages.push_back(std::move(sweep));
  plan.stages.push_back(std::move(merge));
  plan.stages.push_back(std::move(report));
  return plan;
}

}  // namespace occsweep
