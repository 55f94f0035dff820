// The replay engine (issue 5): the update events of a point cloud set do not depend on any probability, so they
// are recorded once and replayed for every combination with OctoMap's float arithmetic and clamping.
#pragma once

#include <cstdint>
#include <vector>

#include "occsweep/core/knn_set_distances.hpp"
#include "occsweep/core/mapping_params.hpp"
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
  std::vector<std::uint32_t> hit_scan;       ///< per hit: its scan
  std::vector<std::uint32_t> hit_inner;      ///< per hit: its index j in the scan's z_in (point order kept)
  std::vector<std::uint8_t> uniform;         ///< per voxel: its events' flags when all are equal, else 0
  std::uint32_t longest = 0;                 ///< most events of one voxel
  std::uint64_t scan_voxel_updates = 0;      ///< events in the region over all scans (for reports)
};

/// Records the region voxels' events with the same traversal as the mappers (ScanEventRecorder), scans in
/// parallel (TBB), merged in scan order.
[[nodiscard]] RecordedSet recordSet(const PointCloudSet& set, const GroundTruth& truth, double resolution, double s_c);

/// computeKnnDistances with the scans' k-NN searches in parallel (TBB); the statistics are then accumulated in
/// scan order, so the result is identical.
[[nodiscard]] KnnSetDistances parallelKnnDistances(const PointCloudSet& set, int k, double s_c);

/// F(s_j) (Eq. 8) of every recorded hit for one k and statistics mode.
[[nodiscard]] std::vector<double> hitCdf(const RecordedSet& r, const KnnSetDistances& d, StatsMode stats);

/// Per event, the float sum of l(p(s_j)) over its hits, in point order (unclamped): depends on k, p_u, p_l only.
[[nodiscard]] std::vector<float> knnHitSums(const RecordedSet& r, const std::vector<double>& cdf, double p_u,
                                            double p_l);

/// How to replay one map.
struct ReplayRule {
  float l_min = 0, l_max = 0;
  VoxelUpdateRule<float> update;           ///< l_in, l_out, variant (OctoMap: l_in = l_out = l(p_m), default)
  float octomap_hit = 0;                   ///< OctoMap: l(p_h) for every hit
  const std::vector<float>* knn_hit_sums = nullptr;  ///< k-NN: per-event sums (clamped once when applied)
};

/// Replays every region voxel and returns what the map would say about the region: the same RegionSample that
/// sampleRegion gives for the directly built map (excluded voxels left out, as there).
[[nodiscard]] RegionSample replay(const RecordedSet& r, const ReplayRule& rule);

[[nodiscard]] ReplayRule octomapRule(const MapParams& m);
[[nodiscard]] ReplayRule knnRule(const MapParams& m, const std::vector<float>& hit_sums, UpdateVariant variant);

/// Maps replayed together: they must share the hit rule (OctoMap, or k-NN maps of one k, p_u, p_l).
inline constexpr std::size_t kReplayLanes = 8;

/// The fast path of replay(): up to kReplayLanes maps in one pass over the events (the lanes vectorise), voxels
/// whose events are all alike settled from tables of repeated clamped updates (the same float steps), and
/// TP/FP counted directly at each lane's thresholds (p_t values). Returns per lane the counts per threshold under
/// full truth (excluded voxels count as positives); `observable`, when given, receives the same from the same
/// pass with the excluded voxels left out (observable truth: docs/results-format.md, "Truth").
[[nodiscard]] std::vector<std::vector<ConfusionCounts>> replayCounts(
    const RecordedSet& r, const std::vector<ReplayRule>& lanes, const std::vector<std::vector<double>>& p_t,
    std::vector<std::vector<ConfusionCounts>>* observable = nullptr);

}  // namespace occsweep
