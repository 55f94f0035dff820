// The k-NN inverse sensor model (Eq. 7) and its map update (Algorithm 1) on a liboctomap OcTree.
#pragma once

#include <memory>
#include <mutex>
#include <stdexcept>
#include <unordered_map>

#include <octomap/OcTree.h>

#include "knn_parameters.hpp"
#include "knn_set_distances.hpp"
#include "normal_cdf.hpp"
#include "occsweep/core/flat_key_index.hpp"
#include "occsweep/core/log_odds.hpp"
#include "occsweep/core/occupancy_tree.hpp"
#include "occsweep/core/scan_events.hpp"
#include "occsweep/core/scan_executor.hpp"
#include "occsweep/core/voxel_update_rule.hpp"

namespace occsweep {

/// Builds k-NN maps. The map is a real octomap::OcTree (so it can be written as .ot and classified like
/// OctoMap's); every update goes through OcTree::updateNode(key, delta), which clamps as Eq. 5.
class KnnInverseSensorModel {
 public:
  explicit KnnInverseSensorModel(const KnnParams& params);

  /// Algorithm 1 over the whole set; computes the distances (and, in Batch mode, mu and sigma) first.
  [[nodiscard]] std::unique_ptr<octomap::OcTree> buildMap(const PointCloudSet& set) const;

  /// The same with distances computed beforehand for this set, k and s_c (shared across a sweep). Updates a
  /// flat voxel store scan by scan (the events of scan_events.hpp) and writes the OcTree once at the end.
  [[nodiscard]] std::unique_ptr<octomap::OcTree> buildMap(const PointCloudSet& set,
                                                          const KnnSetDistances& distances) const;

  /// The same with the scans' events recorded on `executor`, `batch` scans at a time (0: twice its concurrency),
  /// and applied in scan order on this thread: the same map, voxel for voxel (docs/architecture.md, "Threads").
  [[nodiscard]] std::unique_ptr<octomap::OcTree> buildMap(const PointCloudSet& set, const KnnSetDistances& distances,
                                                          const ScanExecutor& executor, std::size_t batch = 0) const;

  /// buildMap's steps, for a caller that records the scans on several threads: startBuild, then each scan's
  /// events recorded on its own (recordScan: any thread, one recorder each) and applied in scan order
  /// (applyScan), then finishBuild. Applied in order, the map is buildMap's, voxel for voxel.
  struct DirectBuild {
    std::unique_ptr<octomap::OcTree> tree;  ///< no node until finishBuild; its thresholds give l_min, l_max
    float l_min = 0, l_max = 0;
    FlatKeyIndex store;                    ///< the voxels updated so far
    std::vector<octomap::OcTreeKey> keys;  ///< by store index
    std::vector<float> values;             ///< their log-odds
  };
  [[nodiscard]] DirectBuild startBuild() const;
  void recordScan(ScanEventRecorder& recorder, const Scan& scan, const KnnScanDistances& d, ScanEvents& events) const;
  void applyScan(DirectBuild& build, const ScanEvents& events, const KnnSetDistances& distances, std::size_t t) const;
  [[nodiscard]] std::unique_ptr<octomap::OcTree> finishBuild(DirectBuild&& build) const;

  /// The reference: Algorithm 1 applied through OcTree::updateNode scan by scan, with octomap::KeySet and
  /// liboctomap's ray keys, as plainly as possible. Slower; the tests compare buildMap against it.
  [[nodiscard]] std::unique_ptr<octomap::OcTree> buildMapReference(const PointCloudSet& set,
                                                                   const KnnSetDistances& distances) const;

  /// One scan of the reference with the given mu, sigma.
  void insertScanReference(octomap::OcTree& tree, const Scan& scan, const KnnScanDistances& d, double mu,
                           double sigma) const;

  /// The delta of a voxel holding points with average distances s (Algorithm 1 lines 3-10): the float sum of
  /// l(p(s_j)) in point order, clamped once to [l_min, l_max].
  template <class Distances>
  [[nodiscard]] float hitDelta(const Distances& s, double mu, double sigma, float l_min, float l_max) const;

  [[nodiscard]] const KnnParams& params() const { return params_; }

  /// l_in, l_out and the variant: how each voxel is updated (voxel_update_rule.hpp).
  [[nodiscard]] VoxelUpdateRule<float> updateRule() const { return {l_in_, l_out_, params_.map.variant}; }

 private:
  KnnParams params_;
  float l_in_;   // l(p_m)
  float l_out_;  // l(p'_m)
};

// ---------------------------------------------------------------------------------------------------------

inline KnnInverseSensorModel::KnnInverseSensorModel(const KnnParams& params)
    : params_(params), l_in_(logOdds(params.p_m)), l_out_(logOdds(params.p_m_out)) {
  validate(params_);
}

inline std::unique_ptr<octomap::OcTree> KnnInverseSensorModel::buildMap(const PointCloudSet& set) const {
  return buildMap(set, computeKnnDistances(set, params_.k, params_.map.s_c));
}

namespace detail {
inline void checkDistances(const KnnParams& p, const PointCloudSet& set, const KnnSetDistances& d) {
  if (d.k != p.k || d.s_c != p.map.s_c || d.scans.size() != set.size())
    throw std::invalid_argument("k-NN distances were computed for another k, s_c or point cloud set");
}
}  // namespace detail

template <class Distances>
float KnnInverseSensorModel::hitDelta(const Distances& s, double mu, double sigma, float l_min, float l_max) const {
  float sum = 0.0f;
  for (double s_j : s) sum += logOdds(pointProbability(s_j, mu, sigma, params_.p_u, params_.p_l));
  return std::min(std::max(sum, l_min), l_max);
}

inline std::unique_ptr<octomap::OcTree> KnnInverseSensorModel::buildMap(const PointCloudSet& set,
                                                                       const KnnSetDistances& distances) const {
  detail::checkDistances(params_, set, distances);
  DirectBuild build = startBuild();
  ScanEventRecorder recorder(params_.map.resolution);
  ScanEvents events;
  for (std::size_t t = 0; t < set.size(); ++t) {
    recordScan(recorder, set[t], distances.scans[t], events);
    applyScan(build, events, distances, t);
  }
  return finishBuild(std::move(build));
}

namespace detail {

// Recorders for the calls that run at once: taken as a call starts, given back as it ends. Each grows to its
// scans' windows once, and there are no more than the calls that ever ran together (the executor's concurrency),
// as with one recorder per thread.
class RecorderPool {
 public:
  explicit RecorderPool(double resolution) : resolution_(resolution) {}
  std::unique_ptr<ScanEventRecorder> take() {
    const std::lock_guard lock(mutex_);
    if (free_.empty()) return std::make_unique<ScanEventRecorder>(resolution_);
    auto r = std::move(free_.back());
    free_.pop_back();
    return r;
  }
  void giveBack(std::unique_ptr<ScanEventRecorder> r) {
    const std::lock_guard lock(mutex_);
    free_.push_back(std::move(r));
  }

 private:
  double resolution_;
  std::mutex mutex_;
  std::vector<std::unique_ptr<ScanEventRecorder>> free_;
};

}  // namespace detail

inline std::unique_ptr<octomap::OcTree> KnnInverseSensorModel::buildMap(const PointCloudSet& set,
                                                                       const KnnSetDistances& distances,
                                                                       const ScanExecutor& executor,
                                                                       std::size_t batch) const {
  if (!executor.for_each) return buildMap(set, distances);  // this thread: one recorder, scan after scan
  detail::checkDistances(params_, set, distances);
  if (batch == 0) batch = 2 * std::max<std::size_t>(1, executor.concurrency);
  batch = std::min(batch, std::max<std::size_t>(1, set.size()));
  DirectBuild build = startBuild();
  detail::RecorderPool recorders(params_.map.resolution);
  std::vector<ScanEvents> events(batch);  // one list per place in the batch, applied in scan order
  for (std::size_t first = 0; first < set.size(); first += batch) {
    const std::size_t count = std::min(batch, set.size() - first);
    executor.run(count, [&](std::size_t i) {
      auto recorder = recorders.take();
      recordScan(*recorder, set[first + i], distances.scans[first + i], events[i]);
      recorders.giveBack(std::move(recorder));
    });
    for (std::size_t i = 0; i < count; ++i) applyScan(build, events[i], distances, first + i);
  }
  return finishBuild(std::move(build));
}

inline KnnInverseSensorModel::DirectBuild KnnInverseSensorModel::startBuild() const {
  DirectBuild build;
  build.tree = makeTree(params_.map.resolution, params_.p_max, params_.p_min, params_.p_t);
  build.l_min = build.tree->getClampingThresMinLog();
  build.l_max = build.tree->getClampingThresMaxLog();
  return build;
}

inline void KnnInverseSensorModel::recordScan(ScanEventRecorder& recorder, const Scan& scan, const KnnScanDistances& d,
                                              ScanEvents& events) const {
  recorder.recordAll(scan, d.inner, params_.map.s_c, events);
}

inline void KnnInverseSensorModel::applyScan(DirectBuild& build, const ScanEvents& events,
                                             const KnnSetDistances& distances, std::size_t t) const {
  const auto& d = distances.scans[t];
  const bool online = params_.map.stats == StatsMode::Online;
  const double mu = online ? d.online_mu : distances.mu, sigma = online ? d.online_sigma : distances.sigma;
  const VoxelUpdateRule<float> rule = updateRule();
  std::vector<double> s;
  for (const VoxelEvent& e : events.voxels) {
    const std::uint32_t i = build.store.findOrInsert(e.key);
    if (i == build.values.size()) {
      build.keys.push_back(e.key);
      build.values.push_back(0.0f);  // a new node starts at log-odds 0, as in OctoMap
    }
    float& v = build.values[i];
    const auto voxelHitDelta = [&] {
      s.clear();
      for (std::uint32_t h = 0; h < e.hit_count; ++h) s.push_back(d.s[events.hit_points[e.first_hit + h]]);
      return hitDelta(s, mu, sigma, build.l_min, build.l_max);
    };
    rule.apply(e.flags, voxelHitDelta, [&](float delta) { v = clampedUpdate(v, delta, build.l_min, build.l_max); });
  }
}

inline std::unique_ptr<octomap::OcTree> KnnInverseSensorModel::finishBuild(DirectBuild&& build) const {
  for (std::size_t i = 0; i < build.keys.size(); ++i) build.tree->setNodeValue(build.keys[i], build.values[i]);
  return std::move(build.tree);
}

inline std::unique_ptr<octomap::OcTree> KnnInverseSensorModel::buildMapReference(
    const PointCloudSet& set, const KnnSetDistances& distances) const {
  detail::checkDistances(params_, set, distances);
  auto tree = makeTree(params_.map.resolution, params_.p_max, params_.p_min, params_.p_t);
  for (std::size_t t = 0; t < set.size(); ++t) {
    const auto& d = distances.scans[t];
    const bool online = params_.map.stats == StatsMode::Online;
    insertScanReference(*tree, set[t], d, online ? d.online_mu : distances.mu,
                        online ? d.online_sigma : distances.sigma);
  }
  return tree;
}

inline void KnnInverseSensorModel::insertScanReference(octomap::OcTree& tree, const Scan& scan, const KnnScanDistances& d,
                                              double mu, double sigma) const {
  using octomap::OcTreeKey;
  const float l_min = tree.getClampingThresMinLog();
  const float l_max = tree.getClampingThresMaxLog();

  // Lines 3-10: sum l(p(s_j)) over the points j of each voxel (in point order, float as OctoMap), clamp once.
  std::unordered_map<OcTreeKey, float, OcTreeKey::KeyHash> hits;
  std::vector<bool> is_inner(scan.points.size(), false);
  for (std::size_t j = 0; j < d.inner.size(); ++j) {
    const auto& p = scan.points[d.inner[j]];
    is_inner[d.inner[j]] = true;
    OcTreeKey key;
    if (!tree.coordToKeyChecked(p, key)) continue;  // outside the octree: OctoMap drops it too
    hits[key] += logOdds(pointProbability(d.s[j], mu, sigma, params_.p_u, params_.p_l));
  }

  // Lines 11 and 14: voxels crossed by rays to z_in points, and by rays to z_out points cut at s_c, with
  // OctoMap's own traversal (origin voxel included, end voxel excluded), as computeUpdate does.
  octomap::KeySet crossed_in, crossed_out;
  octomap::KeyRay ray;
  for (std::size_t i = 0; i < scan.points.size(); ++i) {
    const auto& p = scan.points[i];
    if (is_inner[i]) {
      if (tree.computeRayKeys(scan.origin, p, ray)) crossed_in.insert(ray.begin(), ray.end());
    } else {
      const octomap::point3d direction = (p - scan.origin).normalized();
      const octomap::point3d cut = scan.origin + direction * float(params_.map.s_c);
      if (tree.computeRayKeys(scan.origin, cut, ray)) crossed_out.insert(ray.begin(), ray.end());
    }
  }

  // Each voxel's events as the fast build records them, then the one update rule through OcTree::updateNode.
  std::unordered_map<OcTreeKey, std::uint8_t, OcTreeKey::KeyHash> flags;
  for (const auto& [key, sum] : hits) flags[key] |= kHit;
  for (const auto& key : crossed_in) flags[key] |= kCrossedIn;
  for (const auto& key : crossed_out) flags[key] |= kCrossedOut;
  const VoxelUpdateRule<float> rule = updateRule();
  for (const auto& [key, f] : flags)
    rule.apply(f, [&, &key = key] { return std::min(std::max(hits.at(key), l_min), l_max); },
               [&, &key = key](float delta) { tree.updateNode(key, delta); });
}

}  // namespace occsweep
