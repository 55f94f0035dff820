// The replay engine's fast path: several maps per pass, closed-form voxels, counts without sorting.
#include <algorithm>
#include <array>
#include <stdexcept>

#include "occsweep/core/log_odds.hpp"
#include "occsweep/core/scan_events.hpp"
#include "occsweep/core/voxel_update_rule.hpp"
#include "occsweep/sweeps/replay.hpp"

namespace occsweep {
namespace {

using Lanes = std::array<float, kReplayLanes>;

// OctoMap's clamped update on every lane: value += delta, then clamp (OccupancyOcTreeBase::updateNodeLogOdds).
inline void update(Lanes& v, const Lanes& d, const Lanes& lo, const Lanes& hi) {
  for (std::size_t l = 0; l < kReplayLanes; ++l) {
    const float sum = v[l] + d[l];
    v[l] = sum < lo[l] ? lo[l] : (sum > hi[l] ? hi[l] : sum);
  }
}

}  // namespace

std::vector<std::vector<ConfusionCounts>> replayCounts(const RecordedSet& r, const std::vector<ReplayRule>& rules,
                                                       const std::vector<std::vector<double>>& p_t,
                                                       std::vector<std::vector<ConfusionCounts>>* observable) {
  const std::size_t n = rules.size();
  if (n == 0 || n > kReplayLanes || p_t.size() != n) throw std::invalid_argument("replayCounts: 1 to 8 lanes");
  const std::vector<float>* sums = rules[0].knn_hit_sums;
  VoxelUpdateRule<Lanes> lanes_rule;
  lanes_rule.variant = rules[0].update.variant;
  Lanes lo{}, hi{}, hit{};
  for (std::size_t l = 0; l < kReplayLanes; ++l) {
    const ReplayRule& rule = rules[std::min(l, n - 1)];  // spare lanes repeat the last map; never counted
    if (rule.knn_hit_sums != sums || rule.update.variant != lanes_rule.variant)
      throw std::invalid_argument("replayCounts: lanes must share their hit rule");
    lo[l] = rule.l_min, hi[l] = rule.l_max, hit[l] = rule.octomap_hit;
    lanes_rule.l_in[l] = rule.update.l_in, lanes_rule.l_out[l] = rule.update.l_out;
  }
  // table[c][m]: the value after m equal updates of kind c from 0 (c: in, out, OctoMap hit), step by step.
  std::array<std::vector<Lanes>, 3> table;
  const Lanes* deltas[3] = {&lanes_rule.l_in, &lanes_rule.l_out, &hit};
  for (int c = 0; c < 3; ++c) {
    table[c].assign(r.longest + 1, Lanes{});
    for (std::uint32_t m = 1; m <= r.longest; ++m) {
      table[c][m] = table[c][m - 1];
      update(table[c][m], *deltas[c], lo, hi);
    }
  }
  // Counting without a compare-and-increment per voxel, lane and threshold: each lane's thresholds are sorted
  // ascending, a voxel adds one to reach[j], j = how many of them its value reaches (value >= l(p_t), the same float
  // comparison), and the voxels at or above the s-th threshold are the sum of reach[j] over j > s.
  std::vector<std::vector<float>> thresholds(n);
  std::vector<std::vector<std::size_t>> order(n);  // order[l][s]: the index in p_t[l] of the s-th smallest
  // Excluded voxels (truth value 2) are all true voxels: they reach their own counter, which full truth adds to
  // TP and observable truth leaves out; FP and TN are the same under both.
  std::vector<std::vector<std::uint64_t>> reach_tp(n), reach_fp(n), reach_excluded(n);
  for (std::size_t l = 0; l < n; ++l) {
    std::vector<float> unsorted;
    for (double p : p_t[l]) unsorted.push_back(logOdds(p));
    order[l].resize(unsorted.size());
    for (std::size_t t = 0; t < unsorted.size(); ++t) order[l][t] = t;
    std::stable_sort(order[l].begin(), order[l].end(), [&](std::size_t a, std::size_t b) { return unsorted[a] < unsorted[b]; });
    for (std::size_t t : order[l]) thresholds[l].push_back(unsorted[t]);
    reach_tp[l].assign(unsorted.size() + 1, 0);
    reach_fp[l].assign(unsorted.size() + 1, 0);
    reach_excluded[l].assign(unsorted.size() + 1, 0);
  }
  const std::uint32_t voxels = std::uint32_t(r.truth.size());
  for (std::uint32_t v = 0; v < voxels; ++v) {
    const std::uint32_t begin = r.voxel_first[v], end = r.voxel_first[v + 1];
    if (begin == end) continue;  // unknown: counted as FN or TN below
    Lanes value{};
    const std::uint8_t u = r.uniform[v];
    if (u == kCrossedIn || u == kCrossedOut) {
      value = table[u == kCrossedIn ? 0 : 1][end - begin];
    } else if (u == kHit && !sums) {
      value = table[2][end - begin];
    } else {
      const auto hitDelta = [&](std::uint32_t e) {
        if (!sums) return hit;
        Lanes d;
        const float s = (*sums)[e];  // clamped once per lane (Algorithm 1 line 6-10)
        for (std::size_t l = 0; l < kReplayLanes; ++l) d[l] = std::min(std::max(s, lo[l]), hi[l]);
        return d;
      };
      for (std::uint32_t e = begin; e < end; ++e)
        lanes_rule.apply(r.flags[e], [&] { return hitDelta(e); }, [&](const Lanes& d) { update(value, d, lo, hi); });
    }
    auto& reach = r.truth[v] == 0 ? reach_fp : (r.truth[v] == 1 ? reach_tp : reach_excluded);
    for (std::size_t l = 0; l < n; ++l) {
      std::size_t j = 0;
      for (const float threshold : thresholds[l]) j += value[l] >= threshold;
      ++reach[l][j];
    }
  }
  std::vector<std::vector<ConfusionCounts>> counts(n);
  if (observable) observable->assign(n, {});
  for (std::size_t l = 0; l < n; ++l) {
    counts[l].assign(p_t[l].size(), ConfusionCounts{});
    if (observable) (*observable)[l].assign(p_t[l].size(), ConfusionCounts{});
    std::uint64_t tp = 0, fp = 0, excluded_tp = 0;
    for (std::size_t s = thresholds[l].size(); s-- > 0;) {
      tp += reach_tp[l][s + 1], fp += reach_fp[l][s + 1], excluded_tp += reach_excluded[l][s + 1];
      ConfusionCounts& c = counts[l][order[l][s]];
      c.tp = tp + excluded_tp, c.fp = fp, c.fn = r.positives - c.tp, c.tn = r.negatives - fp;
      if (observable) {
        ConfusionCounts& o = (*observable)[l][order[l][s]];
        o.tp = tp, o.fp = fp, o.fn = r.positives - r.excluded - tp, o.tn = r.negatives - fp;
      }
    }
  }
  return counts;
}

}  // namespace occsweep
