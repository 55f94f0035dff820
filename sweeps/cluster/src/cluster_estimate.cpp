// The cost model of cluster_estimate.hpp: measured tasks per kind, carried to the tasks of a new plan.
#include "occsweep/sweeps/cluster_estimate.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

namespace occsweep {
namespace {

/// A kind of task: its stage and, for a results task, its grid.
std::string kindOf(const std::string& stage, const ClusterTask& task) {
  return task.expect_grid.empty() ? stage : stage + " " + task.expect_grid;
}

/// What the measured tasks of one kind cost, per task of `shards` shards.
struct KindCost {
  double cpu_seconds = 0, wall_seconds = 0;
  std::uint64_t peak_bytes = 0, shards = 1;
  std::size_t tasks = 0;
};

std::map<std::string, KindCost> kindCosts(const ClusterPlan& measured_plan,
                                          const std::vector<TaskMeasurement>& measured) {
  std::map<std::pair<std::string, std::uint64_t>, const TaskMeasurement*> last;  // each task's last success
  for (const TaskMeasurement& m : measured)
    if (m.exit_code == 0) last[{m.stage, m.task}] = &m;
  std::map<std::string, KindCost> kinds;
  for (const ClusterStage& stage : measured_plan.stages)
    for (const ClusterTask& task : stage.tasks) {
      const auto it = last.find({stage.name, task.index});
      if (it == last.end() || it->second->label != task.label) continue;
      KindCost& k = kinds[kindOf(stage.name, task)];
      k.cpu_seconds += it->second->cpu_seconds;
      k.wall_seconds += it->second->wall_seconds;
      k.peak_bytes = std::max(k.peak_bytes, it->second->peak_bytes);
      k.shards = task.expect_shards;
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
      const double share = double(k.shards) / double(std::max<std::uint64_t>(task.expect_shards, 1));
      ++e.modelled;
      e.cpu_seconds += k.cpu_seconds * share;
      e.longest_seconds = std::max(e.longest_seconds, k.wall_seconds * share);
      e.peak_bytes = std::max(e.peak_bytes, k.peak_bytes);
    }
  }
  return out;
}

double estimatedWallSeconds(const std::vector<StageEstimate>& stages, int cores, int cores_per_task) {
  double wall = 0;
  for (const StageEstimate& s : stages) {
    const double at_once = std::max(1.0, std::floor(double(cores) / double(std::max(cores_per_task, 1))));
    const double parallel = s.cpu_seconds / (at_once * double(std::max(cores_per_task, 1)));
    wall += std::max(parallel, s.longest_seconds);
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
