// Running a plan: as chained Slurm job arrays (submit, resubmit), or on this machine (run-local).
#pragma once

#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include "occsweep/sweeps/cluster_state.hpp"

namespace occsweep {

struct SubmitReport {
  std::vector<Submission> submitted;   ///< one per stage that had tasks to run, in order
  std::vector<std::string> cancelled;  ///< JOBID_TASK of tasks whose dependency had failed
};

/// Submits every task not done (and everything downstream of one) as one array per stage, chained with
/// --dependency=afterok, and records each array in DIR/submissions.jsonl. `resubmit` false refuses a plan that was
/// submitted before. Refuses while tasks of the plan are running or pending (they would be run twice).
SubmitReport submitPlan(const ClusterPlan& plan, const std::filesystem::path& dir, bool resubmit, std::ostream& log);

/// Runs the tasks that are not done on this machine, `jobs` at a time, stage after stage (a stage starts when the
/// one before succeeded, like afterok). Logs in DIR/logs/local-<stage>-<task>.log; progress on stderr unless
/// `quiet` (failures, warnings and a stop are printed always). Returns the number of failed tasks (0: the plan is
/// done).
[[nodiscard]] std::size_t runLocal(const ClusterPlan& plan, const std::filesystem::path& dir, int jobs,
                                   bool quiet = false);

}  // namespace occsweep
