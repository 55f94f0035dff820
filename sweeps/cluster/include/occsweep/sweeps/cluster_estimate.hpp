// What a plan will cost before anything runs, from a measured run of a plan of the same kind (docs/cluster.md,
// "Cost estimate"): run-local measures every task (cluster_state.hpp, TaskMeasurement); each task of the new plan
// costs what the measured tasks of its kind cost.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "occsweep/sweeps/cluster_plan.hpp"
#include "occsweep/sweeps/cluster_state.hpp"

namespace occsweep {

/// One stage's expected cost.
struct StageEstimate {
  std::string stage;
  std::size_t tasks = 0, modelled = 0;  ///< the stage's tasks, and how many have a measured kind
  double cpu_seconds = 0;               ///< expected CPU time of the modelled tasks together
  double longest_seconds = 0;           ///< expected wall time of the longest task
  std::uint64_t peak_bytes = 0;         ///< the largest measured peak memory of the stage's kinds
  std::vector<double> task_seconds;     ///< expected wall time of each modelled task
};

/// The model, per kind of task: a kind is the stage and, for a results task, its grid and shard count. A kind's CPU and
/// wall time per task are the means over its measured tasks (each task's last successful run: exit 0, output
/// checked); its peak memory is the largest measured. A task of a kind never measured is not modelled
/// (StageEstimate::modelled counts the others): the model does not extrapolate to other shard counts.
[[nodiscard]] std::vector<StageEstimate> estimatePlan(const ClusterPlan& plan, const ClusterPlan& measured_plan,
                                                      const std::vector<TaskMeasurement>& measured);

/// Expected wall time of the plan on `cores` cores, each task using `cores_per_task`: stage after stage, a stage
/// takes its CPU time spread over the cores, but no less than its tasks take when each starts on the first free
/// slot of cores, longest first (three tasks of a minute on two slots: two minutes).
[[nodiscard]] double estimatedWallSeconds(const std::vector<StageEstimate>& stages, int cores, int cores_per_task);

/// The estimate's margin: --time is twice the longest expected task (at least 10 minutes), --mem one and a half
/// times the peak (at least 256 MB), as sbatch reads them ("HH:MM:SS", "NNNM").
[[nodiscard]] std::string timeWithMargin(double longest_seconds);
[[nodiscard]] std::string memWithMargin(std::uint64_t peak_bytes);

}  // namespace occsweep
