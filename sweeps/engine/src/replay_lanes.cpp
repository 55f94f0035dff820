// The replay engine's fast path: many maps per pass, closed-form voxels, counts without sorting; and the same for
// filters, whose events happen per lane when their gate extremes reach the lane's threshold.
//
// A pass holds up to kReplayPassLanes maps in vectors of four floats. A voxel's events are a serial chain of
// updates, add then clamp, so one voxel's time is that chain's latency: the more lanes share it, and the more
// voxels are replayed side by side, the cheaper each lane (docs/performance.md, "Replay counting"). The float
// operations of every lane and their order are exactly OctoMap's: value = clamp(value + delta) (clampedUpdate,
// log_odds.hpp), starting from 0.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <span>
#include <stdexcept>

#include "occsweep/core/log_odds.hpp"
#include "occsweep/core/scan_events.hpp"
#include "occsweep/core/voxel_update_rule.hpp"
#include "occsweep/sweeps/replay.hpp"

namespace occsweep {
namespace {

// Four lanes in one vector register (GCC's vector extension, lowered for any target). Its operators mean, lane by
// lane, what the scalar ones mean (IEEE float, the same comparisons and selections), whatever the instructions.
using Quad = float __attribute__((vector_size(16)));
constexpr std::size_t kQuadLanes = 4;
static_assert(kReplayPassLanes % kQuadLanes == 0);

// The lanes of one pass: Q vectors of four.
template <std::size_t Q>
using Lanes = std::array<Quad, Q>;

template <std::size_t Q>
inline float lane(const Lanes<Q>& v, std::size_t l) {
  return v[l / kQuadLanes][l % kQuadLanes];
}
template <std::size_t Q>
inline void setLane(Lanes<Q>& v, std::size_t l, float x) {
  v[l / kQuadLanes][l % kQuadLanes] = x;
}

inline Quad splat(float x) { return Quad{x, x, x, x}; }

// OctoMap's clamped update on the four lanes of one vector, clampedUpdate's comparisons in its order
// (OccupancyOcTreeBase::updateNodeLogOdds): value += delta; below l_min gives l_min, else above l_max gives l_max.
inline Quad clampedQuad(Quad v, Quad d, Quad lo, Quad hi) {
  const Quad sum = v + d;
  const Quad below_hi = sum > hi ? hi : sum;
  return sum < lo ? lo : below_hi;
}

// The same on every lane of a pass. kOrderedBounds, where no lane has l_min > l_max (orderedBounds): the last step
// tests l_min > below_hi instead of sum < l_min, which gives the same value: the tests can differ only where
// sum > l_max (below_hi = l_max), and there both are false (sum < l_min would need l_min > l_max; so would
// l_min > l_max). Each step is then one instruction, the vector min and max, instead of a compare and a select
// (docs/performance.md, "Replay counting").
template <bool kOrderedBounds = false, std::size_t Q>
inline void update(Lanes<Q>& v, const Lanes<Q>& d, const Lanes<Q>& lo, const Lanes<Q>& hi) {
  for (std::size_t i = 0; i < Q; ++i) {
    if constexpr (kOrderedBounds) {
      const Quad sum = v[i] + d[i];
      const Quad below_hi = sum > hi[i] ? hi[i] : sum;
      v[i] = lo[i] > below_hi ? lo[i] : below_hi;
    } else {
      v[i] = clampedQuad(v[i], d[i], lo[i], hi[i]);
    }
  }
}

// A lane mask: all bits set on lanes where a comparison held.
using LaneMask = std::int32_t __attribute__((vector_size(16)));

// What every lane of one pass shares (the hit rule, the variant) and what each has of its own (clamp bounds, l_in,
// l_out, OctoMap's l_hit); spare lanes repeat the pass's last map and are never counted.
template <std::size_t Q>
struct LaneRules {
  std::size_t counted = 0;                   ///< lanes that are maps
  Lanes<Q> lo{}, hi{}, hit{};
  VoxelUpdateRule<Lanes<Q>> rule;
  const std::vector<float>* hits = nullptr;  ///< per-event hit deltas (PointSum, PointMax); Constant: nullptr
  bool clamp_hits = false;                   ///< PointSum: each lane clamps the event's sum once
};

template <std::size_t Q>
LaneRules<Q> laneRules(std::span<const ReplayRule> rules) {
  LaneRules<Q> lanes;
  lanes.counted = rules.size();
  lanes.hits = rules[0].event_hits;
  lanes.clamp_hits = rules[0].clamp_event_hits;
  lanes.rule.variant = rules[0].update.variant;
  for (std::size_t l = 0; l < Q * kQuadLanes; ++l) {
    const ReplayRule& rule = rules[std::min(l, rules.size() - 1)];
    setLane(lanes.lo, l, rule.l_min), setLane(lanes.hi, l, rule.l_max), setLane(lanes.hit, l, rule.constant_hit);
    setLane(lanes.rule.l_in, l, rule.update.l_in), setLane(lanes.rule.l_out, l, rule.update.l_out);
  }
  return lanes;
}

void requireSharedHitRule(const std::vector<ReplayRule>& rules, const char* who) {
  for (const ReplayRule& rule : rules)
    if (rule.event_hits != rules[0].event_hits || rule.clamp_event_hits != rules[0].clamp_event_hits ||
        rule.update.variant != rules[0].update.variant)
      throw std::invalid_argument(std::string(who) + ": lanes must share their hit rule");
}

// table[c][m]: the value after m equal updates of kind c from 0 (c: in, out, OctoMap hit), step by step.
template <std::size_t Q>
using StepTables = std::array<std::vector<Lanes<Q>>, 3>;

template <std::size_t Q>
StepTables<Q> stepTables(const LaneRules<Q>& lanes, std::uint32_t longest) {
  StepTables<Q> table;
  const Lanes<Q>* deltas[3] = {&lanes.rule.l_in, &lanes.rule.l_out, &lanes.hit};
  for (int c = 0; c < 3; ++c) {
    table[c].assign(longest + 1, Lanes<Q>{});
    for (std::uint32_t m = 1; m <= longest; ++m) {
      table[c][m] = table[c][m - 1];
      update(table[c][m], *deltas[c], lanes.lo, lanes.hi);
    }
  }
  return table;
}

// Where a pass's hit deltas come from: OctoMap's constant l_hit per lane, or each event's from the points
// (eventHits), clamped once per lane (PointSum, Algorithm 1 lines 6-10) or not (PointMax).
enum class HitSource { Constant, ClampedSum, Max };

template <std::size_t Q>
HitSource hitSourceOf(const LaneRules<Q>& lanes) {
  if (!lanes.hits) return HitSource::Constant;
  return lanes.clamp_hits ? HitSource::ClampedSum : HitSource::Max;
}

// The hit delta of event e on every lane; a clamped sum is std::min(std::max(sum, l_min), l_max) lane by lane.
template <HitSource kSource, std::size_t Q>
inline Lanes<Q> hitDelta(const LaneRules<Q>& lanes, std::uint32_t e) {
  if constexpr (kSource == HitSource::Constant) {
    return lanes.hit;
  } else {
    const Quad s = splat((*lanes.hits)[e]);
    Lanes<Q> d;
    for (std::size_t i = 0; i < Q; ++i) {
      if constexpr (kSource == HitSource::ClampedSum) {
        const Quad raised = s < lanes.lo[i] ? lanes.lo[i] : s;
        d[i] = lanes.hi[i] < raised ? lanes.hi[i] : raised;
      } else {
        d[i] = s;
      }
    }
    return d;
  }
}

// The Default variant's one update per event (VoxelUpdateRule: the hit, else l_in, else l_out), without the rule's
// branches, which the mixed events of a voxel mispredict: the delta by the event's flags from a table of 8
// (docs/performance.md, "Replay counting"). A hit read from the points keeps its branch: hits are a few percent of
// the events, and choosing their delta without a branch cost every event more (measured). Flags 0 (no update) has
// no entry: a pass takes this path only when every event's flags are 1 to 7 (byFlagsApplies).
template <std::size_t Q>
using FlagDeltas = std::array<Lanes<Q>, 8>;

template <std::size_t Q>
FlagDeltas<Q> flagDeltas(const LaneRules<Q>& lanes) {
  FlagDeltas<Q> by_flags{};
  for (std::uint8_t f = 1; f < 8; ++f)
    by_flags[f] = f & kHit ? lanes.hit : (f & kCrossedIn ? lanes.rule.l_in : lanes.rule.l_out);
  return by_flags;
}

bool byFlagsApplies(const RecordedSet& r, UpdateVariant variant) {
  std::uint8_t lowest = 0xFF, highest = 0;  // branch-free, so that the compiler vectorises it
  for (const std::uint8_t f : r.flags) lowest = f < lowest ? f : lowest, highest = f > highest ? f : highest;
  return variant == UpdateVariant::Default && (r.flags.empty() || (lowest >= 1 && highest <= 7));
}

// Where every lane has l_min <= l_max (or a NaN bound), so that update may take its shorter form.
template <std::size_t Q>
bool orderedBounds(const LaneRules<Q>& lanes) {
  for (std::size_t l = 0; l < Q * kQuadLanes; ++l)
    if (lane(lanes.lo, l) > lane(lanes.hi, l)) return false;
  return true;
}

template <HitSource kSource, bool kOrderedBounds, std::size_t Q>
inline void byFlagsStep(const RecordedSet& r, std::uint32_t e, const LaneRules<Q>& lanes, const FlagDeltas<Q>& by_flags,
                        Lanes<Q>& value) {
  const std::uint8_t f = r.flags[e];
  if constexpr (kSource != HitSource::Constant)
    if (f & kHit) return update<kOrderedBounds>(value, hitDelta<kSource>(lanes, e), lanes.lo, lanes.hi);
  update<kOrderedBounds>(value, by_flags[f], lanes.lo, lanes.hi);
}

template <HitSource kSource, bool kOrderedBounds, std::size_t Q>
inline Lanes<Q> byFlagsValue(const RecordedSet& r, std::uint32_t v, const LaneRules<Q>& lanes,
                             const FlagDeltas<Q>& by_flags) {
  Lanes<Q> value{};
  for (std::uint32_t e = r.voxel_first[v]; e < r.voxel_first[v + 1]; ++e)
    byFlagsStep<kSource, kOrderedBounds>(r, e, lanes, by_flags, value);
  return value;
}

// Two voxels at once, event by event in turn: a voxel's updates are a serial chain (add, then clamp) whose latency
// bounds its time, and two independent chains take about the time of one (three or four at once: no faster).
template <HitSource kSource, bool kOrderedBounds, std::size_t Q>
inline void byFlagsValues(const RecordedSet& r, std::uint32_t va, std::uint32_t vb, const LaneRules<Q>& lanes,
                          const FlagDeltas<Q>& by_flags, Lanes<Q>& a, Lanes<Q>& b) {
  const std::uint32_t a_begin = r.voxel_first[va], a_end = r.voxel_first[va + 1];
  const std::uint32_t b_begin = r.voxel_first[vb], b_end = r.voxel_first[vb + 1];
  a = Lanes<Q>{}, b = Lanes<Q>{};
  const std::uint32_t both = std::min(a_end - a_begin, b_end - b_begin);
  for (std::uint32_t k = 0; k < both; ++k) {
    byFlagsStep<kSource, kOrderedBounds>(r, a_begin + k, lanes, by_flags, a);
    byFlagsStep<kSource, kOrderedBounds>(r, b_begin + k, lanes, by_flags, b);
  }
  for (std::uint32_t e = a_begin + both; e < a_end; ++e)
    byFlagsStep<kSource, kOrderedBounds>(r, e, lanes, by_flags, a);
  for (std::uint32_t e = b_begin + both; e < b_end; ++e)
    byFlagsStep<kSource, kOrderedBounds>(r, e, lanes, by_flags, b);
}

// Any variant: event by event through the one update rule.
template <HitSource kSource, std::size_t Q>
inline Lanes<Q> ruleValue(const RecordedSet& r, std::uint32_t begin, std::uint32_t end, const LaneRules<Q>& lanes) {
  Lanes<Q> value{};
  for (std::uint32_t e = begin; e < end; ++e)
    lanes.rule.apply(r.flags[e], [&] { return hitDelta<kSource>(lanes, e); },
                     [&](const Lanes<Q>& d) { update(value, d, lanes.lo, lanes.hi); });
  return value;
}

// What one pass replays with: its lanes, their tables of equal updates, and the Default variant's deltas by flags.
template <std::size_t Q>
struct Pass {
  LaneRules<Q> lanes;
  StepTables<Q> table;
  FlagDeltas<Q> by_flags;
};

template <std::size_t Q>
Pass<Q> makePass(const RecordedSet& r, std::span<const ReplayRule> rules) {
  Pass<Q> pass{laneRules<Q>(rules), {}, {}};
  pass.table = stepTables(pass.lanes, r.longest);
  pass.by_flags = flagDeltas(pass.lanes);
  return pass;
}

// Whether a known voxel's value comes from the tables: all its events are alike, and their delta is a lane's own.
template <HitSource kSource>
inline bool fromTables(const RecordedSet& r, std::uint32_t v) {
  const std::uint8_t u = r.uniform[v];
  return u == kCrossedIn || u == kCrossedOut || (u == kHit && kSource == HitSource::Constant);
}

// The table (StepTables) of a voxel whose events are all alike: in, out, or OctoMap's hit.
inline std::size_t tableOf(std::uint8_t uniform) {
  return uniform == kCrossedIn ? 0 : (uniform == kCrossedOut ? 1 : 2);
}

// How a pass replays the events of a voxel: through the update rule (any variant), or by the table of deltas by
// flags (the Default variant, every event flagged: byFlagsApplies), with update's shorter form where the lanes'
// bounds allow it (orderedBounds).
enum class Kernel { Rule, ByFlags, ByFlagsOrderedBounds };

template <std::size_t Q>
Kernel kernelOf(const LaneRules<Q>& lanes, bool by_flags) {
  if (!by_flags) return Kernel::Rule;
  return orderedBounds(lanes) ? Kernel::ByFlagsOrderedBounds : Kernel::ByFlags;
}

// One known voxel's value on every lane: from the tables when all its events are alike, else event by event.
template <HitSource kSource, Kernel kKernel, std::size_t Q>
inline Lanes<Q> voxelValue(const RecordedSet& r, std::uint32_t v, const Pass<Q>& pass) {
  const std::uint32_t begin = r.voxel_first[v], end = r.voxel_first[v + 1];
  if (fromTables<kSource>(r, v)) return pass.table[tableOf(r.uniform[v])][end - begin];
  if constexpr (kKernel == Kernel::Rule)
    return ruleValue<kSource>(r, begin, end, pass.lanes);
  else
    return byFlagsValue<kSource, kKernel == Kernel::ByFlagsOrderedBounds>(r, v, pass.lanes, pass.by_flags);
}

// Calls body.template operator()<kSource, kKernel>() with the pass's hit source and kernel as constants, so that
// the voxel loop tests neither.
template <std::size_t Q, class Body>
void withKernel(const LaneRules<Q>& lanes, Kernel kernel, Body&& body) {
  const auto bySource = [&]<Kernel kKernel>() {
    switch (hitSourceOf(lanes)) {
      case HitSource::Constant: return body.template operator()<HitSource::Constant, kKernel>();
      case HitSource::ClampedSum: return body.template operator()<HitSource::ClampedSum, kKernel>();
      case HitSource::Max: return body.template operator()<HitSource::Max, kKernel>();
    }
  };
  switch (kernel) {
    case Kernel::Rule: return bySource.template operator()<Kernel::Rule>();
    case Kernel::ByFlags: return bySource.template operator()<Kernel::ByFlags>();
    case Kernel::ByFlagsOrderedBounds: return bySource.template operator()<Kernel::ByFlagsOrderedBounds>();
  }
}

// The passes over `n` lanes: as few as kReplayPassLanes allows, of equal width (20 maps: 2 x 10, not 16 + 4), each
// called as body.template operator()<Q>(first, count) with Q vectors of four lanes.
template <class Body>
void forEachPass(std::size_t n, Body&& body) {
  static_assert(kReplayPassLanes == 4 * kQuadLanes, "one case below per width");
  const std::size_t passes = (n + kReplayPassLanes - 1) / kReplayPassLanes;
  const std::size_t width = (n + passes - 1) / passes;
  for (std::size_t first = 0; first < n; first += width) {
    const std::size_t count = std::min(width, n - first);
    switch ((count + kQuadLanes - 1) / kQuadLanes) {
      case 1: body.template operator()<1>(first, count); break;
      case 2: body.template operator()<2>(first, count); break;
      case 3: body.template operator()<3>(first, count); break;
      default: body.template operator()<4>(first, count); break;
    }
  }
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
    unsorted.reserve(p_t[l].size());  // sized once: a map may have a million thresholds (docs/robustness.md, "Limits")
    for (double p : p_t[l]) unsorted.push_back(logOdds(p));
    LaneThresholds& t = lanes[l];
    t.order.resize(unsorted.size());
    for (std::size_t i = 0; i < unsorted.size(); ++i) t.order[i] = i;
    std::stable_sort(t.order.begin(), t.order.end(), [&](std::size_t a, std::size_t b) { return unsorted[a] < unsorted[b]; });
    t.sorted.reserve(unsorted.size());
    for (std::size_t i : t.order) t.sorted.push_back(unsorted[i]);
    t.reach_tp.assign(unsorted.size() + 1, 0);
    t.reach_fp.assign(unsorted.size() + 1, 0);
    t.reach_excluded.assign(unsorted.size() + 1, 0);
  }
  return lanes;
}

// One voxel's value on one lane counted at that lane's thresholds (see LaneThresholds).
inline void countValue(const RecordedSet& r, std::uint32_t v, float value, LaneThresholds& t) {
  std::size_t j = 0;
  for (const float threshold : t.sorted) j += value >= threshold;
  ++(r.truth[v] == 0 ? t.reach_fp : (r.truth[v] == 1 ? t.reach_tp : t.reach_excluded))[j];
}

template <std::size_t Q>
inline void countLanes(const RecordedSet& r, std::uint32_t v, const Lanes<Q>& value, std::size_t counted,
                       std::span<LaneThresholds> thresholds) {
  for (std::size_t l = 0; l < counted; ++l) countValue(r, v, lane(value, l), thresholds[l]);
}

template <HitSource kSource, Kernel kKernel, std::size_t Q>
void countReach(const RecordedSet& r, const Pass<Q>& pass, std::span<LaneThresholds> thresholds) {
  const std::uint32_t voxels = std::uint32_t(r.truth.size());
  for (std::uint32_t v = 0; v < voxels; ++v) {
    if (r.voxel_first[v] == r.voxel_first[v + 1]) continue;  // unknown: counted as FN or TN below
    countLanes(r, v, voxelValue<kSource, kKernel>(r, v, pass), pass.lanes.counted, thresholds);
  }
}

// countReach in the Default variant: the voxels that need their events replayed, two at a time (byFlagsValues).
// The counts are sums, so the order in which voxels are counted does not change them.
template <HitSource kSource, Kernel kKernel, std::size_t Q>
void countReachInPairs(const RecordedSet& r, const Pass<Q>& pass, std::span<LaneThresholds> thresholds) {
  const std::uint32_t voxels = std::uint32_t(r.truth.size());
  const std::size_t counted = pass.lanes.counted;
  std::optional<std::uint32_t> waiting;
  for (std::uint32_t v = 0; v < voxels; ++v) {
    if (r.voxel_first[v] == r.voxel_first[v + 1]) continue;  // unknown: counted as FN or TN below
    if (fromTables<kSource>(r, v)) {
      countLanes(r, v, voxelValue<kSource, kKernel>(r, v, pass), counted, thresholds);
    } else if (!waiting) {
      waiting = v;
    } else {
      Lanes<Q> a, b;
      byFlagsValues<kSource, kKernel == Kernel::ByFlagsOrderedBounds>(r, *waiting, v, pass.lanes, pass.by_flags, a, b);
      countLanes(r, *waiting, a, counted, thresholds);
      countLanes(r, v, b, counted, thresholds);
      waiting.reset();
    }
  }
  if (waiting) countLanes(r, *waiting, voxelValue<kSource, kKernel>(r, *waiting, pass), counted, thresholds);
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

std::vector<std::vector<ConfusionCounts>> countsOfLanes(const RecordedSet& r,
                                                        const std::vector<LaneThresholds>& thresholds,
                                                        std::vector<std::vector<ConfusionCounts>>* observable) {
  const std::size_t n = thresholds.size();
  std::vector<std::vector<ConfusionCounts>> counts(n);
  if (observable) observable->assign(n, {});
  for (std::size_t l = 0; l < n; ++l)
    countsFromReach(r, thresholds[l], counts[l], observable ? &(*observable)[l] : nullptr);
  return counts;
}

// A filter's gates on the lanes of one pass: per lane and scan the threshold, and per scan the lowest and highest
// over the lanes, so that a voxel whose events every lane keeps (or none does) is settled without a lane loop.
struct GateLanes {
  std::size_t column = 0;
  std::vector<double> lowest, highest;  ///< per scan
  std::vector<float> lanes;             ///< per scan, a pass's lanes: each gate as a float bound (floatGate)
};

// A float bound g' such that, for every float x, x >= g' exactly when x >= g (compared as doubles, as keptFlags
// does): the least float not below g. float(g) rounds to nearest; one step up when that fell below g. A NaN stays
// NaN (no x reaches it), a g above every float becomes +inf (only +inf reaches it).
inline float floatGate(double g) {
  const float f = float(g);
  return double(f) < g ? std::nextafter(f, std::numeric_limits<float>::infinity()) : f;
}

GateLanes gateLanes(std::size_t column, std::span<const std::vector<double>> gates) {
  GateLanes g{column, {}, {}, {}};
  const std::size_t scans = gates.front().size();
  g.lowest.assign(scans, std::numeric_limits<double>::infinity());
  g.highest.assign(scans, -std::numeric_limits<double>::infinity());
  for (const auto& lane : gates)
    for (std::size_t t = 0; t < scans; ++t) {
      g.lowest[t] = std::min(g.lowest[t], lane[t]);
      g.highest[t] = std::max(g.highest[t], lane[t]);
    }
  g.lanes.assign(scans * kReplayPassLanes, std::numeric_limits<float>::quiet_NaN());  // spare lanes keep nothing
  for (std::size_t l = 0; l < gates.size(); ++l)
    for (std::size_t t = 0; t < scans; ++t) g.lanes[t * kReplayPassLanes + l] = floatGate(gates[l][t]);
  return g;
}

// Event e's kExtremes gate extremes of one gate column.
inline const float* eventExtremes(const RecordedSet& r, std::uint32_t e, std::size_t column) {
  return r.extremes.data() + (std::size_t(e) * r.gate_columns + column) * kExtremes;
}

// The flags of event e that a gate of threshold `gate` keeps: each kind happens when its extreme reaches it.
inline std::uint8_t keptFlags(const RecordedSet& r, std::uint32_t e, std::size_t column, double gate) {
  const float* x = eventExtremes(r, e, column);
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

// Every lane of a mixed voxel, event by event: each lane keeps the kinds whose extreme reaches its gate, then
// takes VoxelUpdateRule::apply's updates for its kept flags, lane by lane in selections: the hit where kept; then,
// where no hit was kept or in the Literal variant, l_in where a ray to an in-range point was kept, else l_out
// where a cut ray was. `known`: lanes with any kept event (the others stay unknown).
template <std::size_t Q>
void gatedLaneValues(const RecordedSet& r, std::uint32_t v, const LaneRules<Q>& lanes, const GateLanes& g,
                     Lanes<Q>& value, std::array<LaneMask, Q>& known) {
  const bool literal = lanes.rule.variant == UpdateVariant::Literal;
  value = Lanes<Q>{};
  known = {};
  for (std::uint32_t e = r.voxel_first[v]; e < r.voxel_first[v + 1]; ++e) {
    const std::uint8_t f = r.flags[e];
    const float* x = eventExtremes(r, e, g.column);
    const float* gate = g.lanes.data() + std::size_t(r.event_scan[e]) * kReplayPassLanes;
    const LaneMask none{};
    for (std::size_t i = 0; i < Q; ++i) {
      Quad lane_gate;
      std::memcpy(&lane_gate, gate + i * kQuadLanes, sizeof lane_gate);
      const LaneMask hit = (f & kHit) ? LaneMask(splat(x[kHitExtreme]) >= lane_gate) : none;
      const LaneMask in = (f & kCrossedIn) ? LaneMask(splat(x[kCrossedInExtreme]) >= lane_gate) : none;
      const LaneMask out = (f & kCrossedOut) ? LaneMask(splat(x[kCrossedOutExtreme]) >= lane_gate) : none;
      known[i] |= hit | in | out;
      value[i] = hit ? clampedQuad(value[i], lanes.hit[i], lanes.lo[i], lanes.hi[i]) : value[i];
      const LaneMask miss = (literal ? ~none : ~hit) & (in | out);
      const Quad delta = in ? lanes.rule.l_in[i] : lanes.rule.l_out[i];
      value[i] = miss ? clampedQuad(value[i], delta, lanes.lo[i], lanes.hi[i]) : value[i];
    }
  }
}

template <HitSource kSource, Kernel kKernel, std::size_t Q>
void countGatedReach(const RecordedSet& r, const Pass<Q>& pass, const GateLanes& g,
                     std::span<LaneThresholds> thresholds) {
  const std::uint32_t voxels = std::uint32_t(r.truth.size());
  for (std::uint32_t v = 0; v < voxels; ++v) {
    if (r.voxel_first[v] == r.voxel_first[v + 1]) continue;  // unknown on every lane
    const GateOutcome outcome = gateOutcome(r, v, g);
    if (outcome == GateOutcome::NoneKeep) continue;
    if (outcome == GateOutcome::AllKeep) {
      countLanes(r, v, voxelValue<kSource, kKernel>(r, v, pass), pass.lanes.counted, thresholds);
      continue;
    }
    Lanes<Q> value;
    std::array<LaneMask, Q> known;
    gatedLaneValues(r, v, pass.lanes, g, value, known);
    for (std::size_t l = 0; l < pass.lanes.counted; ++l)
      if (known[l / kQuadLanes][l % kQuadLanes]) countValue(r, v, lane(value, l), thresholds[l]);
  }
}

}  // namespace

std::vector<std::vector<ConfusionCounts>> replayCounts(const RecordedSet& r, const std::vector<ReplayRule>& rules,
                                                       const std::vector<std::vector<double>>& p_t,
                                                       std::vector<std::vector<ConfusionCounts>>* observable) {
  if (rules.empty() || p_t.size() != rules.size()) throw std::invalid_argument("replayCounts: one p_t list per lane");
  requireSharedHitRule(rules, "replayCounts");
  std::vector<LaneThresholds> thresholds = laneThresholds(p_t);
  const bool by_flags = byFlagsApplies(r, rules[0].update.variant);
  forEachPass(rules.size(), [&]<std::size_t Q>(std::size_t first, std::size_t count) {
    const Pass<Q> pass = makePass<Q>(r, std::span(rules).subspan(first, count));
    const std::span<LaneThresholds> lanes_thresholds = std::span(thresholds).subspan(first, count);
    withKernel(pass.lanes, kernelOf(pass.lanes, by_flags), [&]<HitSource kSource, Kernel kKernel>() {
      if constexpr (kKernel == Kernel::Rule) countReach<kSource, kKernel>(r, pass, lanes_thresholds);
      else countReachInPairs<kSource, kKernel>(r, pass, lanes_thresholds);
    });
  });
  return countsOfLanes(r, thresholds, observable);
}

std::vector<std::vector<ConfusionCounts>> replayGatedCounts(const RecordedSet& r, const std::vector<ReplayRule>& rules,
                                                            std::size_t column, const LaneGates& gates,
                                                            const std::vector<std::vector<double>>& p_t,
                                                            std::vector<std::vector<ConfusionCounts>>* observable) {
  if (rules.empty() || p_t.size() != rules.size() || gates.size() != rules.size())
    throw std::invalid_argument("replayGatedCounts: each lane with its thresholds and gates");
  if (rules[0].event_hits) throw std::invalid_argument("replayGatedCounts: a filter's hit rule must be constant");
  if (column >= r.gate_columns) throw std::invalid_argument("replayGatedCounts: no such gate column recorded");
  requireSharedHitRule(rules, "replayGatedCounts");
  std::vector<LaneThresholds> thresholds = laneThresholds(p_t);
  const bool by_flags = byFlagsApplies(r, rules[0].update.variant);
  forEachPass(rules.size(), [&]<std::size_t Q>(std::size_t first, std::size_t count) {
    const Pass<Q> pass = makePass<Q>(r, std::span(rules).subspan(first, count));
    const GateLanes g = gateLanes(column, std::span(gates).subspan(first, count));
    const std::span<LaneThresholds> lanes_thresholds = std::span(thresholds).subspan(first, count);
    withKernel(pass.lanes, kernelOf(pass.lanes, by_flags), [&]<HitSource kSource, Kernel kKernel>() {
      if constexpr (kSource == HitSource::Constant) countGatedReach<kSource, kKernel>(r, pass, g, lanes_thresholds);
    });
  });
  return countsOfLanes(r, thresholds, observable);
}

}  // namespace occsweep
