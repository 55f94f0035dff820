// What one scan does to each voxel, before any probability is chosen: hit (holds an in-range point), crossed by
// a ray to an in-range point, crossed by a ray cut at s_c. Both mappers' updates, and the replay engine, are
// functions of these events; they depend only on the points, the resolution and s_c.
#pragma once

#include <cstdint>
#include <vector>

#include <octomap/OcTree.h>

#include "flat_key_index.hpp"
#include "point_cloud_set.hpp"

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

/// Computes a scan's events for the voxels `keep(key)` accepts, with OctoMap's semantics: in-range test
/// (p - origin).norm() <= s_c as computeUpdate, liboctomap's own computeRayKeys (origin voxel included, end voxel
/// excluded), rays beyond s_c cut at origin + direction * (float) s_c. `inner` are the z_in indices.
class ScanEventRecorder {
 public:
  explicit ScanEventRecorder(double resolution) : grid_(resolution) {}

  template <class Keep>
  void record(const Scan& scan, const std::vector<std::uint32_t>& inner, double s_c, Keep&& keep, ScanEvents& out);

  [[nodiscard]] const octomap::OcTree& grid() const { return grid_; }

 private:
  octomap::OcTree grid_;  // only for OctoMap's key arithmetic and ray traversal; never holds nodes
  octomap::KeyRay ray_;
  FlatKeyIndex index_;  // key -> position in ScanEvents::voxels
  std::vector<std::pair<std::uint32_t, std::uint32_t>> hits_;  // (voxel, j) in point order
  std::vector<std::uint32_t> is_inner_;
};

// ---------------------------------------------------------------------------------------------------------

template <class Keep>
void ScanEventRecorder::record(const Scan& scan, const std::vector<std::uint32_t>& inner, double s_c, Keep&& keep,
                               ScanEvents& out) {
  out.voxels.clear();
  out.hit_points.clear();
  hits_.clear();
  index_.clear();
  auto slot = [&](const octomap::OcTreeKey& key) {
    const std::uint32_t v = index_.findOrInsert(key);
    if (v == out.voxels.size()) out.voxels.push_back(VoxelEvent{key, 0, 0, 0});
    return v;
  };
  is_inner_.assign(scan.points.size(), 0);
  for (std::uint32_t j = 0; j < inner.size(); ++j) {
    is_inner_[inner[j]] = 1;
    octomap::OcTreeKey key;
    if (!grid_.coordToKeyChecked(scan.points[inner[j]], key) || !keep(key)) continue;
    const std::uint32_t v = slot(key);
    out.voxels[v].flags |= kHit;
    hits_.emplace_back(v, j);
  }
  for (std::size_t i = 0; i < scan.points.size(); ++i) {
    const auto& p = scan.points[i];
    std::uint8_t flag = kCrossedIn;
    bool ok;
    if (is_inner_[i]) {
      ok = grid_.computeRayKeys(scan.origin, p, ray_);
    } else {
      const octomap::point3d direction = (p - scan.origin).normalized();
      ok = grid_.computeRayKeys(scan.origin, scan.origin + direction * float(s_c), ray_);
      flag = kCrossedOut;
    }
    if (!ok) continue;
    for (const auto& key : ray_)
      if (keep(key)) out.voxels[slot(key)].flags |= flag;
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
