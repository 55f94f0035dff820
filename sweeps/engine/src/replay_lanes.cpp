// The replay engine's fast path: several maps per pass, closed-form voxels, counts without sorting; and the same
// for filters, whose events happen per lane when their gate extremes reach the lane's threshold.
#include <algorithm>
#include <array>
#include <limits>
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

// What every lane of one pass shares (the hit rule, the variant) and what each has of its own (clamp bounds, l_in,
// l_out, OctoMap's l_hit); spare lanes repeat the last map and are never counted.
struct LaneRules {
  Lanes lo{}, hi{}, hit{};
  VoxelUpdateRule<Lanes> rule;
  const std::vector<float>* hits = nullptr;  ///< per-event hit deltas (PointSum, PointMax); Constant: nullptr
  bool clamp_hits = false;                   ///< PointSum: each lane clamps the event's sum once
};

LaneRules laneRules(const std::vector<ReplayRule>& rules) {
  const std::size_t n = rules.size();
  LaneRules lanes;
  lanes.hits = rules[0].event_hits;
  lanes.clamp_hits = rules[0].clamp_event_hits;
  lanes.rule.variant = rules[0].update.variant;
  for (std::size_t l = 0; l < kReplayLanes; ++l) {
    const ReplayRule& rule = rules[std::min(l, n - 1)];
    if (rule.event_hits != lanes.hits || rule.clamp_event_hits != lanes.clamp_hits ||
        rule.update.variant != lanes.rule.variant)
      throw std::invalid_argument("replayCounts: lanes must share their hit rule");
    lanes.lo[l] = rule.l_min, lanes.hi[l] = rule.l_max, lanes.hit[l] = rule.constant_hit;
    lanes.rule.l_in[l] = rule.update.l_in, lanes.rule.l_out[l] = rule.update.l_out;
  }
  return lanes;
}

// table[c][m]: the value after m equal updates of kind c from 0 (c: in, out, OctoMap hit), step by step.
using StepTables = std::array<std::vector<Lanes>, 3>;

StepTables stepTables(const LaneRules& lanes, std::uint32_t longest) {
  StepTables table;
  const Lanes* deltas[3] = {&lanes.rule.l_in, &lanes.rule.l_out, &lanes.hit};
  for (int c = 0; c < 3; ++c) {
    table[c].assign(longest + 1, Lanes{});
    for (std::uint32_t m = 1; m <= longest; ++m) {
      table[c][m] = table[c][m - 1];
      update(table[c][m], *deltas[c], lanes.lo, lanes.hi);
    }
  }
  return table;
}

// Counting without a compare-and-increment per voxel, lane and threshold: each lane's thresholds are sorted
// ascending, a voxel adds one to reach[j], j = how many of them its value reaches (value >= l(p_t), the same float
// comparison), and the voxels at or above the s-th threshold are the sum of reach[j] over j > s. Excluded voxels
// (truth value 2) are all true voxels: they reach their own counter, which full truth adds to TP and observable
// truth leaves out; FP and TN are the same under both.
struct LaneThresholds {
  std::vector<float> sorted;             ///< l(p_t) ascending
  std::vector<std::size_t> order;        ///< order[s]: the index in p_t of the s-th smallest
  std::vector<std::uint64_t> reach_tp, reach_fp, reach_excluded;
};

std::vector<LaneThresholds> laneThresholds(const std::vector<std::vector<double>>& p_t) {
  std::vector<LaneThresholds> lanes(p_t.size());
  for (std::size_t l = 0; l < p_t.size(); ++l) {
    std::vector<float> unsorted;
    for (double p : p_t[l]) unsorted.push_back(logOdds(p));
    LaneThresholds& t = lanes[l];
    t.order.resize(unsorted.size());
    for (std::size_t i = 0; i < unsorted.size(); ++i) t.order[i] = i;
    std::stable_sort(t.order.begin(), t.order.end(), [&](std::size_t a, std::size_t b) { return unsorted[a] < unsorted[b]; });
    for (std::size_t i : t.order) t.sorted.push_back(unsorted[i]);
    t.reach_tp.assign(unsorted.size() + 1, 0);
    t.reach_fp.assign(unsorted.size() + 1, 0);
    t.reach_excluded.assign(unsorted.size() + 1, 0);
  }
  return lanes;
}

// One known voxel's value on every lane: from the tables when all its events are alike, else event by event
// through the one update rule.
inline Lanes voxelValue(const RecordedSet& r, std::uint32_t v, const LaneRules& lanes, const StepTables& table) {
  const std::uint32_t begin = r.voxel_first[v], end = r.voxel_first[v + 1];
  const std::uint8_t u = r.uniform[v];
  if (u == kCrossedIn || u == kCrossedOut) return table[u == kCrossedIn ? 0 : 1][end - begin];
  if (u == kHit && !lanes.hits) return table[2][end - begin];
  const auto hitDelta = [&](std::uint32_t e) {
    if (!lanes.hits) return lanes.hit;
    Lanes d;
    const float s = (*lanes.hits)[e];
    if (!lanes.clamp_hits) return d.fill(s), d;
    for (std::size_t l = 0; l < kReplayLanes; ++l) d[l] = std::min(std::max(s, lanes.lo[l]), lanes.hi[l]);  // Algorithm 1 lines 6-10
    return d;
  };
  Lanes value{};
  for (std::uint32_t e = begin; e < end; ++e)
    lanes.rule.apply(r.flags[e], [&] { return hitDelta(e); }, [&](const Lanes& d) { update(value, d, lanes.lo, lanes.hi); });
  return value;
}

// One voxel's value on one lane counted at that lane's thresholds (see LaneThresholds).
inline void countValue(const RecordedSet& r, std::uint32_t v, float value, LaneThresholds& t) {
  std::size_t j = 0;
  for (const float threshold : t.sorted) j += value >= threshold;
  ++(r.truth[v] == 0 ? t.reach_fp : (r.truth[v] == 1 ? t.reach_tp : t.reach_excluded))[j];
}

void countReach(const RecordedSet& r, const LaneRules& lanes, const StepTables& table,
                std::vector<LaneThresholds>& thresholds) {
  const std::uint32_t voxels = std::uint32_t(r.truth.size());
  for (std::uint32_t v = 0; v < voxels; ++v) {
    if (r.voxel_first[v] == r.voxel_first[v + 1]) continue;  // unknown: counted as FN or TN below
    const Lanes value = voxelValue(r, v, lanes, table);
    for (std::size_t l = 0; l < thresholds.size(); ++l) countValue(r, v, value[l], thresholds[l]);
  }
}

// Counts at every threshold, in p_t's order, from the voxels reaching each: full truth, and observable truth.
void countsFromReach(const RecordedSet& r, const LaneThresholds& t, std::vector<ConfusionCounts>& counts,
                     std::vector<ConfusionCounts>* observable) {
  counts.assign(t.order.size(), ConfusionCounts{});
  if (observable) observable->assign(t.order.size(), ConfusionCounts{});
  std::uint64_t tp = 0, fp = 0, excluded_tp = 0;
  for (std::size_t s = t.sorted.size(); s-- > 0;) {
    tp += t.reach_tp[s + 1], fp += t.reach_fp[s + 1], excluded_tp += t.reach_excluded[s + 1];
    ConfusionCounts& c = counts[t.order[s]];
    c.tp = tp + excluded_tp, c.fp = fp, c.fn = r.positives - c.tp, c.tn = r.negatives - fp;
    if (observable) {
      ConfusionCounts& o = (*observable)[t.order[s]];
      o.tp = tp, o.fp = fp, o.fn = r.positives - r.excluded - tp, o.tn = r.negatives - fp;
    }
  }
}

// A filter's gates on the lanes of one pass: per lane and scan the threshold, and per scan the lowest and highest
// over the lanes, so that a voxel whose events every lane keeps (or none does) is settled without a lane loop.
struct GateLanes {
  const LaneGates* gates = nullptr;
  std::size_t column = 0;
  std::vector<double> lowest, highest;  ///< per scan
};

GateLanes gateLanes(const RecordedSet& r, std::size_t column, const LaneGates& gates) {
  if (column >= r.gate_columns) throw std::invalid_argument("replayGatedCounts: no such gate column recorded");
  GateLanes g{&gates, column, {}, {}};
  const std::size_t scans = gates.front().size();
  g.lowest.assign(scans, std::numeric_limits<double>::infinity());
  g.highest.assign(scans, -std::numeric_limits<double>::infinity());
  for (const auto& lane : gates)
    for (std::size_t t = 0; t < scans; ++t) {
      g.lowest[t] = std::min(g.lowest[t], lane[t]);
      g.highest[t] = std::max(g.highest[t], lane[t]);
    }
  return g;
}

// The flags of event e that a gate of threshold `gate` keeps: each kind happens when its extreme reaches it.
inline std::uint8_t keptFlags(const RecordedSet& r, std::uint32_t e, std::size_t column, double gate) {
  const float* x = r.extremes.data() + (std::size_t(e) * r.gate_columns + column) * kExtremes;
  const std::uint8_t f = r.flags[e];
  return std::uint8_t(((f & kHit) && x[kHitExtreme] >= gate ? kHit : 0) |
                      ((f & kCrossedIn) && x[kCrossedInExtreme] >= gate ? kCrossedIn : 0) |
                      ((f & kCrossedOut) && x[kCrossedOutExtreme] >= gate ? kCrossedOut : 0));
}

enum class GateOutcome { AllKeep, NoneKeep, Mixed };

// Whether every lane keeps every event of voxel v as recorded, or no lane keeps any.
GateOutcome gateOutcome(const RecordedSet& r, std::uint32_t v, const GateLanes& g) {
  bool all = true, none = true;
  for (std::uint32_t e = r.voxel_first[v]; e < r.voxel_first[v + 1] && (all || none); ++e) {
    const std::uint32_t t = r.event_scan[e];
    all = all && keptFlags(r, e, g.column, g.highest[t]) == r.flags[e];
    none = none && keptFlags(r, e, g.column, g.lowest[t]) == 0;
  }
  return all ? GateOutcome::AllKeep : (none ? GateOutcome::NoneKeep : GateOutcome::Mixed);
}

// One lane of a mixed voxel, event by event through the one update rule; false when no event happens (unknown).
bool gatedLaneValue(const RecordedSet& r, std::uint32_t v, const LaneRules& lanes, const GateLanes& g, std::size_t l,
                    float& value) {
  const VoxelUpdateRule<float> rule{lanes.rule.l_in[l], lanes.rule.l_out[l], lanes.rule.variant};
  const std::vector<double>& gate = (*g.gates)[l];
  bool known = false;
  value = 0.0f;
  for (std::uint32_t e = r.voxel_first[v]; e < r.voxel_first[v + 1]; ++e) {
    const std::uint8_t flags = keptFlags(r, e, g.column, gate[r.event_scan[e]]);
    if (!flags) continue;
    known = true;
    rule.apply(flags, [&] { return lanes.hit[l]; },
               [&](float d) { value = clampedUpdate(value, d, lanes.lo[l], lanes.hi[l]); });
  }
  return known;
}

void countGatedReach(const RecordedSet& r, const LaneRules& lanes, const StepTables& table, const GateLanes& g,
                     std::vector<LaneThresholds>& thresholds) {
  const std::uint32_t voxels = std::uint32_t(r.truth.size());
  for (std::uint32_t v = 0; v < voxels; ++v) {
    if (r.voxel_first[v] == r.voxel_first[v + 1]) continue;  // unknown on every lane
    const GateOutcome outcome = gateOutcome(r, v, g);
    if (outcome == GateOutcome::NoneKeep) continue;
    if (outcome == GateOutcome::AllKeep) {
      const Lanes value = voxelValue(r, v, lanes, table);
      for (std::size_t l = 0; l < thresholds.size(); ++l) countValue(r, v, value[l], thresholds[l]);
      continue;
    }
    for (std::size_t l = 0; l < thresholds.size(); ++l) {
      float value = 0.0f;
      if (gatedLaneValue(r, v, lanes, g, l, value)) countValue(r, v, value, thresholds[l]);
    }
  }
}

}  // namespace

std::vector<std::vector<ConfusionCounts>> replayCounts(const RecordedSet& r, const std::vector<ReplayRule>& rules,
                                                       const std::vector<std::vector<double>>& p_t,
                                                       std::vector<std::vector<ConfusionCounts>>* observable) {
  const std::size_t n = rules.size();
  if (n == 0 || n > kReplayLanes || p_t.size() != n) throw std::invalid_argument("replayCounts: 1 to 8 lanes");
  const LaneRules lanes = laneRules(rules);
  const StepTables table = stepTables(lanes, r.longest);
  std::vector<LaneThresholds> thresholds = laneThresholds(p_t);
  countReach(r, lanes, table, thresholds);
  std::vector<std::vector<ConfusionCounts>> counts(n);
  if (observable) observable->assign(n, {});
  for (std::size_t l = 0; l < n; ++l) countsFromReach(r, thresholds[l], counts[l], observable ? &(*observable)[l] : nullptr);
  return counts;
}

std::vector<std::vector<ConfusionCounts>> replayGatedCounts(const RecordedSet& r, const std::vector<ReplayRule>& rules,
                                                            std::size_t column, const LaneGates& gates,
                                                            const std::vector<std::vector<double>>& p_t,
                                                            std::vector<std::vector<ConfusionCounts>>* observable) {
  const std::size_t n = rules.size();
  if (n == 0 || n > kReplayLanes || p_t.size() != n || gates.size() != n)
    throw std::invalid_argument("replayGatedCounts: 1 to 8 lanes, each with its thresholds and gates");
  if (rules[0].event_hits) throw std::invalid_argument("replayGatedCounts: a filter's hit rule must be constant");
  const LaneRules lanes = laneRules(rules);
  const StepTables table = stepTables(lanes, r.longest);
  const GateLanes g = gateLanes(r, column, gates);
  std::vector<LaneThresholds> thresholds = laneThresholds(p_t);
  countGatedReach(r, lanes, table, g, thresholds);
  std::vector<std::vector<ConfusionCounts>> counts(n);
  if (observable) observable->assign(n, {});
  for (std::size_t l = 0; l < n; ++l) countsFromReach(r, thresholds[l], counts[l], observable ? &(*observable)[l] : nullptr);
  return counts;
}

}  // namespace occsweep
