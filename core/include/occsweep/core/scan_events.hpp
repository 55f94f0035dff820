// What one scan does to each voxel, before any probability is chosen: hit (holds an in-range point), crossed by
// a ray to an in-range point, crossed by a ray cut at s_c. Both mappers' updates, and the replay engine, are
// functions of these events; they depend only on the points, the resolution and s_c.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <octomap/OcTree.h>

#include "point_cloud_set.hpp"
#include "ray_traversal.hpp"

namespace occsweep {

enum VoxelEventFlags : std::uint8_t { kHit = 1, kCrossedIn = 2, kCrossedOut = 4 };

struct VoxelEvent {
  octomap::OcTreeKey key;
  std::uint8_t flags = 0;
  std::uint32_t first_hit = 0, hit_count = 0;  ///< range in ScanEvents::hit_points
};

struct ScanEvents {
  std::vector<VoxelEvent> voxels;        ///< each touched voxel once, in first-touch order
  std::vector<std::uint32_t> hit_points; ///< per voxel, the z_in indices j of its points, in point order
};

/// An inclusive box of keys: the voxels whose events are kept.
struct KeyWindow {
  std::array<int, 3> lo{}, hi{};
  [[nodiscard]] bool contains(const octomap::OcTreeKey& k) const {
    return k[0] >= lo[0] && k[0] <= hi[0] && k[1] >= lo[1] && k[1] <= hi[1] && k[2] >= lo[2] && k[2] <= hi[2];
  }
  [[nodiscard]] std::uint32_t volume() const {
    return std::uint32_t(hi[0] - lo[0] + 1) * std::uint32_t(hi[1] - lo[1] + 1) * std::uint32_t(hi[2] - lo[2] + 1);
  }
  [[nodiscard]] std::uint32_t index(const octomap::OcTreeKey& k) const {
    return (std::uint32_t(k[0] - lo[0]) * std::uint32_t(hi[1] - lo[1] + 1) + std::uint32_t(k[1] - lo[1])) *
               std::uint32_t(hi[2] - lo[2] + 1) + std::uint32_t(k[2] - lo[2]);
  }
};

/// Computes a scan's events with OctoMap's semantics: in-range test (p - origin).norm() <= s_c as computeUpdate,
/// liboctomap's ray keys (traverseRay: origin voxel included, end voxel excluded), rays beyond s_c cut at
/// origin + direction * (float) s_c. `inner` are the z_in indices. Only voxels inside the window are kept; a
/// dense stamp array over the window removes duplicates without hashing.
class ScanEventRecorder {
 public:
  explicit ScanEventRecorder(double resolution) : grid_(resolution) {}

  /// Keeps the voxels of `window` (rays that cannot reach it are skipped).
  void record(const Scan& scan, const std::vector<std::uint32_t>& inner, double s_c, const KeyWindow& window,
              ScanEvents& out);
  /// Keeps every voxel the scan touches (the window is the cube of half-edge s_c around the origin).
  void recordAll(const Scan& scan, const std::vector<std::uint32_t>& inner, double s_c, ScanEvents& out);

  [[nodiscard]] const octomap::OcTree& grid() const { return grid_; }

 private:
  [[nodiscard]] bool mayReach(const octomap::point3d& a, const octomap::point3d& b, const KeyWindow& w) const;

  octomap::OcTree grid_;  // only for OctoMap's key arithmetic; never holds nodes
  std::vector<std::uint32_t> stamp_, slot_;  // per window cell: generation when last touched, its voxel index
  std::uint32_t generation_ = 0;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> hits_;  // (voxel, j) in point order
  std::vector<std::uint8_t> is_inner_;
};

// ---------------------------------------------------------------------------------------------------------

// Conservative segment-box test in metres with a margin of one voxel: a ray that may touch the window is never
// skipped (the traversal's keys lie within float rounding of the segment).
inline bool ScanEventRecorder::mayReach(const octomap::point3d& a, const octomap::point3d& b, const KeyWindow& w) const {
  const double res = grid_.getResolution();
  double t0 = 0.0, t1 = 1.0;
  for (int i = 0; i < 3; ++i) {
    const double lo = grid_.keyToCoord(octomap::key_type(w.lo[i])) - 1.5 * res;
    const double hi = grid_.keyToCoord(octomap::key_type(w.hi[i])) + 1.5 * res;
    const double p = a(i), d = double(b(i)) - double(a(i));
    if (d == 0.0) {
      if (p < lo || p > hi) return false;
      continue;
    }
    double ta = (lo - p) / d, tb = (hi - p) / d;
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return false;
  }
  return true;
}

inline void ScanEventRecorder::recordAll(const Scan& scan, const std::vector<std::uint32_t>& inner, double s_c,
                                         ScanEvents& out) {
  const octomap::OcTreeKey o = grid_.coordToKey(scan.origin);
  const int half = int(std::ceil(s_c / grid_.getResolution())) + 2;
  KeyWindow w;
  for (int i = 0; i < 3; ++i) {
    w.lo[i] = std::max(0, int(o[i]) - half);
    w.hi[i] = std::min(65535, int(o[i]) + half);
  }
  record(scan, inner, s_c, w, out);
}

inline void ScanEventRecorder::record(const Scan& scan, const std::vector<std::uint32_t>& inner, double s_c,
                                      const KeyWindow& window, ScanEvents& out) {
  out.voxels.clear();
  out.hit_points.clear();
  hits_.clear();
  if (stamp_.size() < window.volume()) {
    stamp_.assign(window.volume(), 0);
    slot_.resize(window.volume());
    generation_ = 0;
  }
  if (++generation_ == 0) {  // wrapped: clear once every 2^32 scans
    std::fill(stamp_.begin(), stamp_.end(), 0);
    generation_ = 1;
  }
  auto slot = [&](const octomap::OcTreeKey& key) -> VoxelEvent& {
    const std::uint32_t cell = window.index(key);
    if (stamp_[cell] != generation_) {
      stamp_[cell] = generation_;
      slot_[cell] = std::uint32_t(out.voxels.size());
      out.voxels.push_back(VoxelEvent{key, 0, 0, 0});
    }
    return out.voxels[slot_[cell]];
  };
  is_inner_.assign(scan.points.size(), 0);
  for (std::uint32_t j = 0; j < inner.size(); ++j) {
    is_inner_[inner[j]] = 1;
    octomap::OcTreeKey key;
    if (!grid_.coordToKeyChecked(scan.points[inner[j]], key) || !window.contains(key)) continue;
    VoxelEvent& e = slot(key);
    e.flags |= kHit;
    hits_.emplace_back(std::uint32_t(&e - out.voxels.data()), j);
  }
  for (std::size_t i = 0; i < scan.points.size(); ++i) {
    const auto& p = scan.points[i];
    const std::uint8_t flag = is_inner_[i] ? kCrossedIn : kCrossedOut;
    const octomap::point3d end =
        is_inner_[i] ? p : scan.origin + (p - scan.origin).normalized() * float(s_c);  // cut as computeUpdate
    if (!mayReach(scan.origin, end, window)) continue;
    traverseRay(grid_, scan.origin, end, [&](const octomap::OcTreeKey& key) {
      if (window.contains(key)) slot(key).flags |= flag;
    });
  }
  // Group the hit points by voxel, keeping point order within each voxel (a counting sort).
  for (const auto& [v, j] : hits_) ++out.voxels[v].hit_count;
  std::uint32_t offset = 0;
  for (auto& v : out.voxels) {
    v.first_hit = offset;
    offset += v.hit_count;
    v.hit_count = 0;
  }
  out.hit_points.resize(offset);
  for (const auto& [v, j] : hits_) out.hit_points[out.voxels[v].first_hit + out.voxels[v].hit_count++] = j;
}

}  // namespace occsweep
