#include "occsweep/sweeps/replay.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "occsweep/core/log_odds.hpp"
#include "occsweep/core/scan_events.hpp"
#include "occsweep/sweeps/tbb_scan_executor.hpp"

namespace occsweep {

namespace {

// A region voxel's index, in 32 bits: recordSet checks the region's volume first.
inline std::uint32_t regionIndex(const KeyWindow& region, const octomap::OcTreeKey& k) {
  return std::uint32_t(region.index(k));
}

// Per region voxel: 0 free, 1 occupied, 2 excluded; and the counts of each.
inline void labelTruth(const GroundTruth& truth, const KeyWindow& region, std::uint32_t voxels, RecordedSet& r) {
  r.truth.assign(voxels, 0);
  for (const auto& k : truth.occupied) r.truth[regionIndex(region, k)] = 1;
  for (const auto& k : truth.excluded) r.truth[regionIndex(region, k)] = 2;
  r.positives = truth.occupied.size();
  r.excluded = truth.excluded.size();
  r.negatives = voxels - r.positives;
}

inline std::vector<ScanEvents> recordScans(const PointCloudSet& set, const KeyWindow& region, double resolution,
                                           double s_c, const SetGateScores& gate_scores) {
  std::vector<ScanEvents> per_scan(set.size());
  tbb::enumerable_thread_specific<ScanEventRecorder> recorders([&] { return ScanEventRecorder(resolution); });
  tbb::parallel_for(std::size_t(0), set.size(), [&](std::size_t t) {
    GateScores scores;
    for (const auto& column : gate_scores) scores.push_back(&column[t]);
    recorders.local().record(set[t], innerPoints(set[t], s_c), s_c, region, per_scan[t], scores);
    per_scan[t].voxels.shrink_to_fit();
  });
  return per_scan;
}

// The stable counting sort of the events by voxel: voxel_first, flags, hit_first, hit_scan, hit_inner.
inline void bucketByVoxel(const std::vector<ScanEvents>& per_scan, const KeyWindow& region, std::uint32_t voxels,
                          RecordedSet& r) {
  std::size_t events_total = 0, hits_total = 0;
  r.voxel_first.assign(voxels + 1, 0);
  for (const ScanEvents& events : per_scan) {
    events_total += events.voxels.size();
    hits_total += events.hit_points.size();
    for (const VoxelEvent& e : events.voxels) ++r.voxel_first[regionIndex(region, e.key) + 1];
  }
  r.scan_voxel_updates = events_total;
  for (std::uint32_t v = 0; v < voxels; ++v) r.voxel_first[v + 1] += r.voxel_first[v];
  // Sorted position of each event: its voxel's next free slot, scans and events taken in order (stable).
  std::vector<std::uint32_t> fill(r.voxel_first.begin(), r.voxel_first.end() - 1);
  auto forEachSorted = [&](auto&& visit) {
    std::copy(r.voxel_first.begin(), r.voxel_first.end() - 1, fill.begin());
    for (std::uint32_t t = 0; t < per_scan.size(); ++t)
      for (const VoxelEvent& e : per_scan[t].voxels) visit(t, e, fill[regionIndex(region, e.key)]++);
  };
  r.flags.resize(events_total);
  r.hit_first.assign(events_total + 1, 0);
  const std::size_t gate_floats = r.gate_columns * kExtremes;
  r.extremes.resize(events_total * gate_floats);
  r.event_scan.resize(gate_floats ? events_total : 0);
  forEachSorted([&](std::uint32_t t, const VoxelEvent& e, std::uint32_t pos) {
    r.flags[pos] = e.flags;
    r.hit_first[pos + 1] = e.hit_count;
    if (!gate_floats) return;
    const std::size_t in_scan = std::size_t(&e - per_scan[t].voxels.data());
    std::copy_n(per_scan[t].extremes.begin() + long(in_scan * gate_floats), gate_floats,
                r.extremes.begin() + long(std::size_t(pos) * gate_floats));
    r.event_scan[pos] = t;
  });
  r.hit_events.reserve(std::size_t(std::count_if(r.hit_first.begin(), r.hit_first.end(), [](auto n) { return n; })));
  for (std::size_t e = 0; e < events_total; ++e) {
    if (r.hit_first[e + 1] != 0) r.hit_events.push_back(std::uint32_t(e));  // its hit count, before the sum
    r.hit_first[e + 1] += r.hit_first[e];
  }
  r.hit_scan.resize(hits_total);
  r.hit_inner.resize(hits_total);
  forEachSorted([&](std::uint32_t t, const VoxelEvent& e, std::uint32_t pos) {
    const std::uint32_t* hits = per_scan[t].hit_points.data() + e.first_hit;
    std::fill_n(r.hit_scan.begin() + r.hit_first[pos], e.hit_count, t);
    std::copy_n(hits, e.hit_count, r.hit_inner.begin() + r.hit_first[pos]);
  });
}

// Per voxel: the flags all its events share (0 if they differ or it has none), and the longest event list.
inline void summarizeVoxels(std::uint32_t voxels, RecordedSet& r) {
  r.uniform.assign(voxels, 0);
  for (std::uint32_t v = 0; v < voxels; ++v) {
    const std::uint32_t begin = r.voxel_first[v], end = r.voxel_first[v + 1];
    r.longest = std::max(r.longest, end - begin);
    if (begin == end) continue;
    std::uint8_t f = r.flags[begin];
    for (std::uint32_t e = begin + 1; e < end && f; ++e)
      if (r.flags[e] != f) f = 0;
    r.uniform[v] = f;
  }
}

}  // namespace

RecordedSet recordSet(const PointCloudSet& set, const GroundTruth& truth, double resolution, double s_c,
                      const SetGateScores& gate_scores) {
  RecordedSet r;
  r.gate_columns = gate_scores.size();
  const auto& lo = truth.region_min_key;
  const auto& hi = truth.region_max_key;
  const KeyWindow region{{lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]}};
  // Voxels are indexed in 32 bits; makeGroundTruth has checked the region against limits().region_voxels.
  checkLimit("evaluation region, voxels", region.volume(), std::numeric_limits<std::uint32_t>::max(),
             "a smaller region");
  const auto voxels = std::uint32_t(region.volume());
  labelTruth(truth, region, voxels, r);
  // Events in scan order, then bucketed by voxel with a stable counting sort done in place over the scans'
  // own lists (three passes: count per voxel, hits per sorted event, copy). Memory matters here (the sweep's
  // peak stays within 3x the points, docs/performance.md "Memory"): no intermediate copy of the events, every
  // vector sized exactly.
  std::vector<ScanEvents> per_scan = recordScans(set, region, resolution, s_c, gate_scores);
  bucketByVoxel(per_scan, region, voxels, r);
  std::vector<ScanEvents>().swap(per_scan);
  summarizeVoxels(voxels, r);
  return r;
}

std::vector<double> recordedHitFeatures(const RecordedSet& r, const PointCloudSet& set, const PointFeature& feature,
                                        double s_c) {
  return feature.valuesAtHits(set, {r.hit_scan, r.hit_inner, s_c}, tbbScanExecutor());
}

std::vector<float> eventHits(const RecordedSet& r, const std::vector<double>& features, const HitRule& hit) {
  if (r.hit_events.empty() && !r.hit_scan.empty())
    throw std::invalid_argument("eventHits: a recorded set without its list of hit events (recordSet makes it)");
  std::vector<float> out(r.flags.size(), 0.0f);
  const bool sum = hit.kind == HitRule::Kind::PointSum;
  // Only the events with hits (a few percent of them): a loop over every event spent more on finding them than on
  // the hits of the paper-scale set (docs/performance.md, "Replay counting").
  for (const std::uint32_t e : r.hit_events) {
    // float, in point order: exactly the direct mappers' hitDeltaOf before its clamp
    float value = sum ? 0.0f : -std::numeric_limits<float>::infinity();
    for (std::uint32_t h = r.hit_first[e]; h < r.hit_first[e + 1]; ++h)
      value = sum ? value + hit.pointLogOdds(features[h]) : std::max(value, hit.pointLogOdds(features[h]));
    out[e] = value;
  }
  return out;
}

ReplayRule replayRule(const MapRule& rule, const std::vector<float>* event_hits) {
  ReplayRule r;
  r.l_min = rule.l_min;
  r.l_max = rule.l_max;
  r.update = rule.update;
  r.constant_hit = rule.hit.l_hit;
  if (rule.hit.kind != HitRule::Kind::Constant) {
    if (!event_hits) throw std::invalid_argument("replayRule: a hit rule that reads points needs its events' hits");
    r.event_hits = event_hits;
    r.clamp_event_hits = rule.hit.kind == HitRule::Kind::PointSum;
  }
  return r;
}

RegionSample replay(const RecordedSet& r, const ReplayRule& rule) {
  RegionSample s;
  s.positives = r.positives - r.excluded;
  s.negatives = r.negatives;
  const float lo = rule.l_min, hi = rule.l_max;
  const auto hitDelta = [&](std::uint32_t e) {
    if (!rule.event_hits) return rule.constant_hit;
    const float d = (*rule.event_hits)[e];
    return rule.clamp_event_hits ? std::min(std::max(d, lo), hi) : d;
  };
  const std::uint32_t voxels = std::uint32_t(r.truth.size());
  for (std::uint32_t v = 0; v < voxels; ++v) {
    const std::uint32_t begin = r.voxel_first[v], end = r.voxel_first[v + 1];
    if (begin == end || r.truth[v] == 2) continue;  // never updated (unknown), or not evaluated
    float value = 0.0f;
    for (std::uint32_t e = begin; e < end; ++e)
      rule.update.apply(
          r.flags[e], [&] { return hitDelta(e); },
          [&](float delta) { value = clampedUpdate(value, delta, lo, hi); });
    (r.truth[v] ? s.positive_log_odds : s.negative_log_odds).push_back(value);
  }
  std::sort(s.positive_log_odds.begin(), s.positive_log_odds.end());
  std::sort(s.negative_log_odds.begin(), s.negative_log_odds.end());
  return s;
}

}  // namespace occsweep
