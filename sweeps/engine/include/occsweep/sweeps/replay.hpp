// The replay engine: the update events of a point cloud set do not depend on any probability, so they
// are recorded once and replayed for every combination with OctoMap's float arithmetic and clamping.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "occsweep/core/mapping_method.hpp"
#include "occsweep/core/point_feature.hpp"
#include "occsweep/core/voxel_update_rule.hpp"
#include "occsweep/eval/confusion.hpp"
#include "occsweep/sweeps/grid.hpp"

namespace occsweep {

/// The events of every region voxel, in scan order. Voxels outside the region never count, so they are not kept.
struct RecordedSet {
  std::vector<std::uint8_t> truth;           ///< per region voxel: 0 free, 1 occupied, 2 occupied but excluded
                                             ///< (GroundTruth::excluded: unobservable)
  std::uint64_t positives = 0, negatives = 0;  ///< under full truth (excluded voxels are positives)
  std::uint64_t excluded = 0;                ///< voxels of truth value 2
  std::vector<std::uint32_t> voxel_first;    ///< events of voxel v: [voxel_first[v], voxel_first[v + 1])
  std::vector<std::uint8_t> flags;           ///< per event: VoxelEventFlags
  std::vector<std::uint32_t> hit_first;      ///< hits of event e: [hit_first[e], hit_first[e + 1])
  std::vector<std::uint32_t> hit_events;     ///< the events with hits, ascending (what eventHits visits)
  std::vector<std::uint32_t> hit_scan;       ///< per hit: its scan
  std::vector<std::uint32_t> hit_inner;      ///< per hit: its index j in the scan's z_in (point order kept)
  std::vector<std::uint8_t> uniform;         ///< per voxel: its events' flags when all are equal, else 0
  std::uint32_t longest = 0;                 ///< most events of one voxel
  std::uint64_t scan_voxel_updates = 0;      ///< events in the region over all scans (for reports)
  // With gate scores (filters: docs/methods.md, "Filters") only:
  std::size_t gate_columns = 0;              ///< gate features recorded
  std::vector<float> extremes;               ///< per event and column, kExtremes floats (ScanEvents::extremes)
  std::vector<std::uint32_t> event_scan;     ///< per event: its scan
};

/// Per gate feature, per scan, per point: the score a filter compares with its threshold (float, as recorded).
using SetGateScores = std::vector<std::vector<std::vector<float>>>;

/// Records the region voxels' events with the same traversal as the mappers (ScanEventRecorder), scans in
/// parallel (TBB), merged in scan order.
/// With `gate_scores`, also each event's gate extremes and scan.
[[nodiscard]] RecordedSet recordSet(const PointCloudSet& set, const GroundTruth& truth, double resolution, double s_c,
                                    const SetGateScores& gate_scores = {});

/// A feature of every recorded hit's point (PointFeature::valuesAtHits, the scans in parallel: TBB), equal to
/// PointFeature::compute's value for it. `s_c`: the one the events were recorded at.
[[nodiscard]] std::vector<double> recordedHitFeatures(const RecordedSet& r, const PointCloudSet& set,
                                                      const PointFeature& feature, double s_c);

/// Per event, its hit delta from its points' features (`hit_features`: recordedHitFeatures) before any clamp: the float
/// sum of pointLogOdds in point order (PointSum), or the largest (PointMax). Depends on the hit rule only.
[[nodiscard]] std::vector<float> eventHits(const RecordedSet& r, const std::vector<double>& hit_features,
                                           const HitRule& hit);

/// How to replay one map.
struct ReplayRule {
  float l_min = 0, l_max = 0;
  VoxelUpdateRule<float> update;           ///< l_in, l_out, variant (OctoMap: l_in = l_out = l(p_m), default)
  float constant_hit = 0;                  ///< HitRule::Constant: the delta of every hit (OctoMap's l(p_h))
  const std::vector<float>* event_hits = nullptr;  ///< PointSum, PointMax: per event (eventHits)
  bool clamp_event_hits = false;           ///< PointSum: clamped once to [l_min, l_max] (Algorithm 1)
};

/// The replay of a method's rule, with its events' hit deltas when the hit rule reads points (eventHits).
[[nodiscard]] ReplayRule replayRule(const MapRule& rule, const std::vector<float>* event_hits);

/// Replays every region voxel and returns what the map would say about the region: the same RegionSample that
/// sampleRegion gives for the directly built map (excluded voxels left out, as there).
[[nodiscard]] RegionSample replay(const RecordedSet& r, const ReplayRule& rule);

/// The most maps replayed in one pass over the events, each a lane: they must share the hit rule (OctoMap, or k-NN
/// maps of one k, p_u, p_l).
inline constexpr std::size_t kReplayPassLanes = 16;

/// The fast path of replay(): maps that share the hit rule replayed together, up to kReplayPassLanes in one pass
/// over the events (the lanes vectorise), voxels whose events are all alike settled from tables of repeated clamped
/// updates (the same float steps), and TP/FP counted directly at each lane's thresholds (p_t values). More maps
/// take more passes over the same event hits. Returns per lane the counts per threshold under full truth (excluded
/// voxels count as positives); `observable`, when given, receives the same from the same pass with the excluded
/// voxels left out (observable truth: docs/results-format.md, "Truth").
[[nodiscard]] std::vector<std::vector<ConfusionCounts>> replayCounts(
    const RecordedSet& r, const std::vector<ReplayRule>& lanes, const std::vector<std::vector<double>>& p_t,
    std::vector<std::vector<ConfusionCounts>>* observable = nullptr);

/// A filter's lanes: per lane, per scan, the gate threshold (PointGate::threshold of the scan's summary).
using LaneGates = std::vector<std::vector<double>>;

/// replayCounts for a filter: each event of lane l happens only when its extreme of gate column `column` reaches
/// the lane's threshold for the event's scan, and a voxel none of whose events happen stays unknown. Lanes share
/// `column` and a constant hit.
[[nodiscard]] std::vector<std::vector<ConfusionCounts>> replayGatedCounts(
    const RecordedSet& r, const std::vector<ReplayRule>& lanes, std::size_t column, const LaneGates& gates,
    const std::vector<std::vector<double>>& p_t, std::vector<std::vector<ConfusionCounts>>* observable = nullptr);

}  // namespace occsweep
