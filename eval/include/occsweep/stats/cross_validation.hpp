// Leave-one-group-out selection of a grid combination (docs/statistics.md).
#pragma once

#include <cstddef>
#include <vector>

namespace occsweep::stats {

/// One held-out group.
struct HeldOutScore {
  std::size_t optimum_combination = 0;  ///< the group's own best (lowest id on ties)
  double optimum = 0.0;                 ///< its AUC on the group: the paper's per-set optimum
  std::size_t chosen_combination = 0;   ///< best mean AUC over the other groups (lowest id on ties)
  double cv_score = 0.0;                ///< the chosen combination's AUC on the held-out group
  double gap = 0.0;                     ///< optimum - cv_score, >= 0
};

struct LeaveOneGroupOut {
  std::vector<HeldOutScore> groups;  ///< in input order
  double mean_optimum = 0.0;
  double mean_cv_score = 0.0;
  double mean_gap = 0.0;
};

/// auc[group][combination]: every row the same length, at least 2 groups and 1 combination, all finite.
/// Throws std::invalid_argument otherwise.
[[nodiscard]] LeaveOneGroupOut leaveOneGroupOut(const std::vector<std::vector<double>>& auc);

}  // namespace occsweep::stats
