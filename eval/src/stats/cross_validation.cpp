#include "occsweep/stats/cross_validation.hpp"

#include <stdexcept>
#include <string>

#include "sample_checks.hpp"

namespace occsweep::stats {

namespace {

void requireRectangularTable(const std::vector<std::vector<double>>& auc) {
  if (auc.size() < 2) throw std::invalid_argument("leave-one-group-out: needs at least 2 groups");
  if (auc.front().empty()) throw std::invalid_argument("leave-one-group-out: needs at least 1 combination");
  for (std::size_t g = 0; g < auc.size(); ++g) {
    if (auc[g].size() != auc.front().size())
      throw std::invalid_argument("leave-one-group-out: group " + std::to_string(g) + " has " +
                                  std::to_string(auc[g].size()) + " combinations, group 0 has " +
                                  std::to_string(auc.front().size()));
    detail::requireFinite(auc[g], "leave-one-group-out");
  }
}

/// Index of the largest value, the lowest index among equals (strict > while scanning upwards).
std::size_t argmaxLowest(const std::vector<double>& values) {
  std::size_t best = 0;
  for (std::size_t c = 1; c < values.size(); ++c)
    if (values[c] > values[best]) best = c;
  return best;
}

/// Per combination, the summed AUC over every group but `held_out`, added in group order so that equal columns
/// give bit-identical sums (ties are then real ties). The sum ranks combinations exactly as the mean does.
std::vector<double> sumsWithout(const std::vector<std::vector<double>>& auc, std::size_t held_out) {
  std::vector<double> sums(auc.front().size(), 0.0);
  for (std::size_t g = 0; g < auc.size(); ++g)
    if (g != held_out)
      for (std::size_t c = 0; c < sums.size(); ++c) sums[c] += auc[g][c];
  return sums;
}

}  // namespace

LeaveOneGroupOut leaveOneGroupOut(const std::vector<std::vector<double>>& auc) {
  requireRectangularTable(auc);
  LeaveOneGroupOut result;
  for (std::size_t g = 0; g < auc.size(); ++g) {
    HeldOutScore score;
    score.optimum_combination = argmaxLowest(auc[g]);
    score.optimum = auc[g][score.optimum_combination];
    score.chosen_combination = argmaxLowest(sumsWithout(auc, g));
    score.cv_score = auc[g][score.chosen_combination];
    score.gap = score.optimum - score.cv_score;
    result.mean_optimum += score.optimum / double(auc.size());
    result.mean_cv_score += score.cv_score / double(auc.size());
    result.mean_gap += score.gap / double(auc.size());
    result.groups.push_back(score);
  }
  return result;
}

}  // namespace occsweep::stats
