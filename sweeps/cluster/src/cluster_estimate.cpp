// The cost model of cluster_estimate.hpp: measured tasks per kind, carried to the tasks of a new plan.
#include "occsweep/sweeps/cluster_estimate.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <map>
#include <queue>
#include <set>
#include <sstream>

#include "occsweep/eval/observable_truth.hpp"

namespace occsweep {
namespace {

namespace fs = std::filesystem;

/// `arg` with the data set's key, as the whole argument or as a path component, written as {dataset}, and a list of
/// ids (point cloud parameter ids) as its count.
std::string shapeOf(const std::string& arg, const std::string& key) {
  if (!arg.empty() && arg.find_first_not_of("0123456789,") == std::string::npos)
    return "{" + std::to_string(std::count(arg.begin(), arg.end(), ',') + 1) + " ids}";
  std::string out;
  std::size_t start = 0;
  for (std::size_t slash; (slash = arg.find('/', start)) != std::string::npos; start = slash + 1) {
    const std::string part = arg.substr(start, slash - start);
    out += (part == key ? "{dataset}" : part) + "/";
  }
  const std::string last = arg.substr(start);
  return out + (last == key ? "{dataset}" : last);
}

/// How many of the report's arguments are its inputs: it compares one merged results file per set and grid and costs
/// in proportion to them, so its kind leaves them out and its costs are per input (docs/cluster.md, "Cost
/// estimate"). Other tasks: 0 (`select` reads one ranking per block, but ranks the same sets however many blocks).
std::size_t inputArguments(const ClusterTask& task) {
  if (task.kind != OutputKind::Comparison) return 0;
  std::size_t n = 0;
  for (std::size_t i = 1; i < task.argv.size(); ++i)
    n += std::find(task.inputs.begin(), task.inputs.end(), task.argv[i]) != task.inputs.end();
  return n;
}

/// A kind of task: tasks of one kind cost alike, whatever their data set.
/// - a results task (sweep, merge): its stage, grid, shard count and sweep settings (resolution, s_c, variant,
///   statistics, truth; an Eq. 16 group's count and seed): a shard's fixed costs do not shrink with more shards, and a
///   group of 1/20 is not the whole grid, so no kind is scaled to another;
/// - any other (generation, select, report): its stage and command, with its data set and its ids left out; the
///   report's inputs by their file names alone (inputArguments: those are counted instead).
std::string kindOf(const std::string& stage, const ClusterTask& task) {
  std::ostringstream k;
  k << stage;
  if (!task.expect_grid.empty()) {
    k << " grid " << task.expect_grid << " shards " << task.expect_shards;
    if (const auto& w = task.expect_work) {
      k << " resolution " << w->map.resolution << " s_c " << w->map.s_c << " variant " << toText(w->map.variant)
        << " stats " << toText(w->map.stats) << " truth " << truthModeName(w->truth);
      if (w->group) k << " group of " << w->group->count << " seed " << w->group->seed;
    }
    return k.str();
  }
  const std::string key = task.label.substr(0, task.label.find(' '));
  // The report's inputs by their own file names (one per grid): a report of other grids is another kind.
  std::set<std::string> input_names;
  for (std::size_t i = 1; i < task.argv.size(); ++i) {
    const bool input = task.kind == OutputKind::Comparison &&
                       std::find(task.inputs.begin(), task.inputs.end(), task.argv[i]) != task.inputs.end();
    if (input)
      input_names.insert(fs::path(task.argv[i]).filename().string());
    else
      k << ' ' << shapeOf(task.argv[i], key);
  }
  for (const std::string& name : input_names) k << " {inputs named " << name << "}";
  return k.str();
}

/// A task's share of its kind's cost: 1, or its input arguments for a kind measured per input.
double unitsOf(const ClusterTask& task) { return double(std::max<std::size_t>(1, inputArguments(task))); }

/// What the measured tasks of one kind cost, per task (per input argument for a task that names its inputs, unitsOf).
struct KindCost {
  double cpu_seconds = 0, wall_seconds = 0;
  std::uint64_t peak_bytes = 0;
  std::size_t tasks = 0;
};

std::map<std::string, KindCost> kindCosts(const ClusterPlan& measured_plan,
                                          const std::vector<TaskMeasurement>& measured) {
  const LastSuccesses last(measured);
  std::map<std::string, KindCost> kinds;
  for (const ClusterStage& stage : measured_plan.stages)
    for (const ClusterTask& task : stage.tasks) {
      const TaskMeasurement* m = last.of(stage.name, task);
      if (!m) continue;
      KindCost& k = kinds[kindOf(stage.name, task)];
      const double units = unitsOf(task);
      k.cpu_seconds += m->cpu_seconds / units;
      k.wall_seconds += m->wall_seconds / units;
      k.peak_bytes = std::max(k.peak_bytes, m->peak_bytes);
      ++k.tasks;
    }
  for (auto& [name, k] : kinds) k.cpu_seconds /= double(k.tasks), k.wall_seconds /= double(k.tasks);
  return kinds;
}

}  // namespace

std::vector<StageEstimate> estimatePlan(const ClusterPlan& plan, const ClusterPlan& measured_plan,
                                        const std::vector<TaskMeasurement>& measured) {
  const std::map<std::string, KindCost> kinds = kindCosts(measured_plan, measured);
  std::vector<StageEstimate> out;
  for (const ClusterStage& stage : plan.stages) {
    StageEstimate& e = out.emplace_back();
    e.stage = stage.name;
    e.tasks = stage.tasks.size();
    for (const ClusterTask& task : stage.tasks) {
      const auto it = kinds.find(kindOf(stage.name, task));
      if (it == kinds.end()) continue;
      const KindCost& k = it->second;
      const double units = unitsOf(task);
      ++e.modelled;
      e.cpu_seconds += k.cpu_seconds * units;
      e.longest_seconds = std::max(e.longest_seconds, k.wall_seconds * units);
      e.task_seconds.push_back(k.wall_seconds * units);
      e.peak_bytes = std::max(e.peak_bytes, k.peak_bytes);
    }
  }
  return out;
}

namespace {

/// When the last of `seconds` ends, each task started on the first of `slots` to come free, longest first.
double listScheduleSeconds(std::vector<double> seconds, std::size_t slots) {
  std::sort(seconds.begin(), seconds.end(), std::greater<>());
  std::priority_queue<double, std::vector<double>, std::greater<>> free_at;
  for (std::size_t i = 0; i < std::min(slots, seconds.size()); ++i) free_at.push(0.0);
  double end = 0;
  for (const double s : seconds) {
    const double start = free_at.top();
    free_at.pop();
    free_at.push(start + s);
    end = std::max(end, start + s);
  }
  return end;
}

}  // namespace

double estimatedWallSeconds(const std::vector<StageEstimate>& stages, int cores, int cores_per_task) {
  double wall = 0;
  for (const StageEstimate& s : stages) {
    const double at_once = std::max(1.0, std::floor(double(cores) / double(std::max(cores_per_task, 1))));
    const double parallel = s.cpu_seconds / (at_once * double(std::max(cores_per_task, 1)));
    wall += std::max({parallel, s.longest_seconds, listScheduleSeconds(s.task_seconds, std::size_t(at_once))});
  }
  return wall;
}

std::string timeWithMargin(double longest_seconds) {
  const long minutes = std::max(10L, long(std::ceil(2.0 * longest_seconds / 60.0)));
  char text[32];
  std::snprintf(text, sizeof text, "%02ld:%02ld:00", minutes / 60, minutes % 60);
  return text;
}

std::string memWithMargin(std::uint64_t peak_bytes) {
  const auto mb = std::uint64_t(std::ceil(1.5 * double(peak_bytes) / (1024.0 * 1024.0)));
  return std::to_string(std::max<std::uint64_t>(256, mb)) + "M";
}

}  // namespace occsweep
