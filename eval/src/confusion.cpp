#include "occsweep/eval/confusion.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "occsweep/core/log_odds.hpp"

namespace occsweep {
namespace {

double ratio(std::uint64_t num, std::uint64_t den) {
  return den == 0 ? std::numeric_limits<double>::quiet_NaN() : double(num) / double(den);
}

// How many values of a sorted vector are >= threshold.
std::uint64_t atLeast(const std::vector<float>& sorted, float threshold) {
  return std::uint64_t(sorted.end() - std::lower_bound(sorted.begin(), sorted.end(), threshold));
}

}  // namespace

double ConfusionCounts::tpr() const { return ratio(tp, tp + fn); }
double ConfusionCounts::fdr() const { return ratio(fp, tp + fp); }
double ConfusionCounts::precision() const { return ratio(tp, tp + fp); }
double ConfusionCounts::fpr() const { return ratio(fp, fp + tn); }

RegionSample sampleRegion(const octomap::OcTree& map, const GroundTruth& truth) {
  RegionSample s;
  forEachRegionVoxel(map, truth, [&](const octomap::OcTreeKey&, bool occupied, const octomap::OcTreeNode* node) {
    (occupied ? s.positives : s.negatives) += 1;
    if (node) (occupied ? s.positive_log_odds : s.negative_log_odds).push_back(node->getLogOdds());
  });
  std::sort(s.positive_log_odds.begin(), s.positive_log_odds.end());
  std::sort(s.negative_log_odds.begin(), s.negative_log_odds.end());
  return s;
}

ConfusionCounts classify(const RegionSample& sample, double p_t) {
  const float threshold = logOdds(p_t);  // OctoMap's occ_prob_thres_log
  ConfusionCounts c;
  c.tp = atLeast(sample.positive_log_odds, threshold);
  c.fp = atLeast(sample.negative_log_odds, threshold);
  c.fn = sample.positives - c.tp;
  c.tn = sample.negatives - c.fp;
  return c;
}

std::vector<ConfusionCounts> classify(const RegionSample& sample, const std::vector<double>& p_t) {
  std::vector<ConfusionCounts> out;
  out.reserve(p_t.size());
  for (double p : p_t) out.push_back(classify(sample, p));
  return out;
}

}  // namespace occsweep
