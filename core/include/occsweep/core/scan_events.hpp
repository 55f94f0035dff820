// What one scan does to each voxel, before any probability is chosen: hit (holds an in-range point), crossed by
// a ray to an in-range point, crossed by a ray cut at s_c. Both mappers' updates, and the replay engine, are
// functions of these events; they depend only on the points, the resolution and s_c.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include <octomap/OcTree.h>

#include "limits.hpp"
#include "point_cloud_set.hpp"
#include "ray_traversal.hpp"

namespace occsweep {

enum VoxelEventFlags : std::uint8_t { kHit = 1, kCrossedIn = 2, kCrossedOut = 4 };

struct VoxelEvent {
  octomap::OcTreeKey key;
  std::uint8_t flags = 0;
  std::uint32_t first_hit = 0, hit_count = 0;  ///< range in ScanEvents::hit_points (first_hit 0 without hits)
};

struct ScanEvents {
  std::vector<VoxelEvent> voxels;        ///< each touched voxel once, in first-touch order
  std::vector<std::uint32_t> hit_points; ///< per voxel, the z_in indices j of its points, in point order
  /// With gate scores (a filter's per-point score, one column each): per voxel and column, the largest score over
  /// the in-range points in it, over the rays to in-range points that cross it, and over the cut rays to points
  /// beyond s_c that cross it (kExtremes floats, -inf where none). A filter that keeps a point when its score reaches
  /// a threshold keeps the voxel's event exactly when that extreme does (docs/methods.md, "Filters").
  std::vector<float> extremes;
};

/// The extremes of one voxel and gate column: ScanEvents::extremes[(voxel * columns + column) * 3 + kind].
enum GateExtreme : std::uint8_t { kHitExtreme = 0, kCrossedInExtreme = 1, kCrossedOutExtreme = 2, kExtremes = 3 };

/// Per gate column, the score of every point of the scan (point order); empty without a gate.
using GateScores = std::vector<const std::vector<float>*>;

/// Computes a scan's events with OctoMap's semantics: in-range test (p - origin).norm() <= s_c as computeUpdate,
/// liboctomap's ray keys (traverseRay: origin voxel included, end voxel excluded), rays beyond s_c cut at
/// origin + direction * (float) s_c. `inner` are the z_in indices. Only voxels inside the window are kept; a
/// dense stamp array over the window removes duplicates without hashing.
class ScanEventRecorder {
 public:
  explicit ScanEventRecorder(double resolution) : grid_(resolution) {}

  /// Keeps the voxels of `window` (rays that cannot reach it are skipped).
  void record(const Scan& scan, const std::vector<std::uint32_t>& inner, double s_c, const KeyWindow& window,
              ScanEvents& out, const GateScores& scores = {});
  /// Keeps every voxel the scan touches (the window: windowOf).
  void recordAll(const Scan& scan, const std::vector<std::uint32_t>& inner, double s_c, ScanEvents& out);

  [[nodiscard]] const octomap::OcTree& grid() const { return grid_; }
  /// The smallest window recordAll needs; LimitError past limits().window_voxels.
  [[nodiscard]] KeyWindow windowOf(const Scan& scan, double s_c) const;

 private:
  // The window in metres grown by 1.5 voxels, once per scan; mayReach tests a segment against it.
  struct ReachBox {
    std::array<double, 3> lo{}, hi{};
  };
  [[nodiscard]] ReachBox reachBox(const KeyWindow& w) const;
  [[nodiscard]] static bool mayReach(const ReachBox& box, const octomap::point3d& a, const octomap::point3d& b);
  // Whether a ray is tested against the window before it is traversed. The test only spares the traversal of rays
  // that miss the window (which visit nothing), so the events are the same either way; a window that holds every
  // ray (windowOf's) skips it: the k-NN build 5 % faster (docs/performance.md).
  enum class RayTest { MayReach, None };
  // record() with the test of its rays; the steps below, in order.
  void recordIn(const Scan& scan, const std::vector<std::uint32_t>& inner, double s_c, const KeyWindow& window,
                ScanEvents& out, const GateScores& scores, RayTest test);
  [[nodiscard]] std::uint16_t startScan(const KeyWindow& window);
  // cells: cells_.data(), passed in so that the ray loop keeps it in a register
  template <bool kGated>
  void mark(std::uint16_t* cells, std::uint32_t cell, std::uint8_t flag, std::uint16_t stamp);
  void markHits(const Scan& scan, const std::vector<std::uint32_t>& inner, const KeyWindow& window, std::uint16_t stamp);
  template <bool kGated>
  void markRays(const Scan& scan, double s_c, const KeyWindow& window, std::uint16_t stamp, RayTest test);
  // Gate scores: the largest score of point i over kind (GateExtreme) in cell's extremes.
  void raiseExtremes(std::uint32_t cell, std::size_t i, std::uint8_t kind);
  void groupHitPoints(ScanEvents& out);

  octomap::OcTree grid_;  // only for OctoMap's key arithmetic; never holds nodes
  // Per window cell, 16 bits: the scan generation (high byte) that last touched it and its flags (low byte).
  // Small enough to stay in cache, which is what makes this faster than hashing every ray key.
  std::vector<std::uint16_t> cells_;
  std::uint8_t generation_ = 0;
  std::vector<std::uint32_t> touched_;                         // cells touched this scan, in first-touch order
  std::uint32_t hit_voxels_ = 0;                                // the first of them, touched by markHits
  static constexpr std::uint32_t kNoCell = ~std::uint32_t(0);   // a free slot of hit_slots_ (cells are below it)
  std::vector<std::pair<std::uint32_t, std::uint32_t>> hit_slots_;  // groupHitPoints' table: (cell, voxel)
  std::vector<std::pair<std::uint32_t, std::uint32_t>> hits_;  // (cell, j) in point order
  std::vector<std::uint8_t> is_inner_;
  // With gate scores only: per window cell its index in touched_ (valid while its stamp is this scan's), and per
  // touched cell its extremes.
  const GateScores* scores_ = nullptr;
  std::vector<std::uint32_t> slot_;
  std::vector<float> extremes_;
};

// ---------------------------------------------------------------------------------------------------------

inline ScanEventRecorder::ReachBox ScanEventRecorder::reachBox(const KeyWindow& w) const {
  const double res = grid_.getResolution();
  ReachBox box;
  for (unsigned i = 0; i < 3; ++i) {
    box.lo[i] = grid_.keyToCoord(octomap::key_type(w.lo[i])) - 1.5 * res;
    box.hi[i] = grid_.keyToCoord(octomap::key_type(w.hi[i])) + 1.5 * res;
  }
  return box;
}

// Conservative segment-box test: a ray that may touch the window is never skipped. The traversal's keys lie within
// float rounding of the segment, far inside the margin of 1.5 voxels, which also covers the rounding of the
// slab test's products with 1 / d. The segment's own box first: no division for rays beside the window.
inline bool ScanEventRecorder::mayReach(const ReachBox& box, const octomap::point3d& a, const octomap::point3d& b) {
  for (unsigned i = 0; i < 3; ++i)
    if (double(std::max(a(i), b(i))) < box.lo[i] || double(std::min(a(i), b(i))) > box.hi[i]) return false;
  double t0 = 0.0, t1 = 1.0;
  for (unsigned i = 0; i < 3; ++i) {
    const double p = a(i), d = double(b(i)) - double(a(i));
    if (d == 0.0) continue;  // inside the slab: the box test above
    const double inverse = 1.0 / d;
    double ta = (box.lo[i] - p) * inverse, tb = (box.hi[i] - p) * inverse;
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return false;
  }
  return true;
}

// The cube of half-edge s_c around the origin, clipped to the keys of the scan's points and origin grown by two
// voxels (float rounding of the traversal): every voxel a point or a ray touches lies in both, so the events are
// the same, and the window's memory follows the scan's extent instead of the cube of s_c / resolution
// (the full cube at --s-c 40 would take 1 GB, at --s-c 81.05 wrap a 32-bit volume). Past the limit: LimitError.
inline KeyWindow ScanEventRecorder::windowOf(const Scan& scan, double s_c) const {
  const double factor = 1.0 / grid_.getResolution();
  auto keyOf = [&](double c) {  // OctoMap's coordToKey, clamped to the key range, in 64 bits
    return int(std::clamp<double>(std::floor(factor * c) + 32768.0, 0.0, 65535.0));
  };
  std::array<int, 3> lo, hi;
  for (int i = 0; i < 3; ++i) lo[i] = hi[i] = keyOf(scan.origin(i));
  for (const auto& p : scan.points)
    for (int i = 0; i < 3; ++i) {
      const int k = keyOf(p(i));
      lo[i] = std::min(lo[i], k);
      hi[i] = std::max(hi[i], k);
    }
  const octomap::OcTreeKey o = grid_.coordToKey(scan.origin);
  const double half = std::ceil(s_c * factor) + 2.0;
  KeyWindow w;
  for (int i = 0; i < 3; ++i) {
    w.lo[i] = std::max({0, lo[i] - 2, int(std::max(0.0, double(o[i]) - half))});
    w.hi[i] = std::min({65535, hi[i] + 2, int(std::min(65535.0, double(o[i]) + half))});
  }
  checkLimit("k-NN key window of a scan (s_c " + std::to_string(s_c) + " m at resolution " +
                 std::to_string(grid_.getResolution()) + " m, clipped to the scan's extent), voxels",
             w.volume(), limits().window_voxels, "--max-window-voxels, or a smaller --s-c or a larger --resolution");
  return w;
}

// windowOf's window holds every ray of the scan: no ray is tested against it.
inline void ScanEventRecorder::recordAll(const Scan& scan, const std::vector<std::uint32_t>& inner, double s_c,
                                         ScanEvents& out) {
  recordIn(scan, inner, s_c, windowOf(scan, s_c), out, {}, RayTest::None);
}

// Forgets the previous scan and returns this scan's stamp (its generation in the high byte).
inline std::uint16_t ScanEventRecorder::startScan(const KeyWindow& window) {
  hits_.clear();
  touched_.clear();
  // Cells are indexed in 32 bits: the limits (window, region) keep windows far below; this guards an override.
  checkLimit("key window, voxels", window.volume(), std::numeric_limits<std::uint32_t>::max(), "a smaller window");
  if (cells_.size() < window.volume()) {
    cells_.assign(window.volume(), 0);
    generation_ = 0;
  }
  if (++generation_ == 0) {  // wrapped after 255 scans: forget every stamp once
    std::fill(cells_.begin(), cells_.end(), 0);
    generation_ = 1;
  }
  return std::uint16_t(generation_) << 8;
}

// kGated: also give a newly touched cell its slot of gate extremes. A template, so that the plain recording's hot
// loop carries no test for it (measured: 12 % more time for octomap-opt's sweep with a run-time test).
template <bool kGated>
inline void ScanEventRecorder::mark(std::uint16_t* cells, std::uint32_t cell, std::uint8_t flag,
                                     std::uint16_t stamp) {
  std::uint16_t& c = cells[cell];
  if ((c & 0xFF00) != stamp) {
    c = stamp;
    if constexpr (kGated) {
      slot_[cell] = std::uint32_t(touched_.size());
      extremes_.resize(extremes_.size() + scores_->size() * kExtremes, -std::numeric_limits<float>::infinity());
    }
    touched_.push_back(cell);
  }
  c |= flag;
}

inline void ScanEventRecorder::raiseExtremes(std::uint32_t cell, std::size_t i, std::uint8_t kind) {
  const std::size_t columns = scores_->size();
  float* e = extremes_.data() + std::size_t(slot_[cell]) * columns * kExtremes + kind;
  for (std::size_t c = 0; c < columns; ++c) e[c * kExtremes] = std::max(e[c * kExtremes], (*(*scores_)[c])[i]);
}

// The voxels holding an in-range point (z_in index j), and which points are in range.
inline void ScanEventRecorder::markHits(const Scan& scan, const std::vector<std::uint32_t>& inner,
                                        const KeyWindow& window, std::uint16_t stamp) {
  is_inner_.assign(scan.points.size(), 0);
  for (std::uint32_t j = 0; j < inner.size(); ++j) {
    is_inner_[inner[j]] = 1;
    octomap::OcTreeKey key;
    if (!grid_.coordToKeyChecked(scan.points[inner[j]], key) || !window.contains(key)) continue;
    const auto cell = std::uint32_t(window.index(key));
    if (scores_) {
      mark<true>(cells_.data(), cell, kHit, stamp);
      raiseExtremes(cell, inner[j], kHitExtreme);
    } else {
      mark<false>(cells_.data(), cell, kHit, stamp);
    }
    hits_.emplace_back(cell, j);
  }
}

// The voxels each ray crosses: to an in-range point, or cut at s_c. The hot loop, kept a function of its own:
// inlined into a caller's loop (recordSet's parallel_for body, the k-NN mapper's), g++ 12 compiles the ray
// loop with 9% (recordSet) and 4% (k-NN build) more instructions (callgrind, built-in scene).
// kGated: also raise the cells' gate extremes (a separate instantiation keeps the plain loop as it was).
template <bool kGated>
[[gnu::noinline]] inline void ScanEventRecorder::markRays(const Scan& scan, double s_c, const KeyWindow& window,
                                                          std::uint16_t stamp, RayTest test) {
  const ReachBox reach = reachBox(window);
  const bool tested = test == RayTest::MayReach;
  for (std::size_t i = 0; i < scan.points.size(); ++i) {
    const auto& p = scan.points[i];
    // A cut ray lies on the ray to its point (within float rounding): when that one misses, no cut is computed.
    if (tested && !mayReach(reach, scan.origin, p)) continue;
    const std::uint8_t flag = is_inner_[i] ? kCrossedIn : kCrossedOut;
    const octomap::point3d end =
        is_inner_[i] ? p : scan.origin + (p - scan.origin).normalized() * float(s_c);  // cut as computeUpdate
    if (tested && !is_inner_[i] && !mayReach(reach, scan.origin, end)) continue;
    // captures by value: the loop's stores to cells could otherwise change them (docs/performance.md)
    std::uint16_t* const cells = cells_.data();
    traverseRayInWindow(grid_, scan.origin, end, window, [this, cells, flag, stamp, i](std::uint64_t index) {
      const auto cell = std::uint32_t(index);
      mark<kGated>(cells, cell, flag, stamp);
      if constexpr (kGated) raiseExtremes(cell, i, flag == kCrossedIn ? kCrossedInExtreme : kCrossedOutExtreme);
      else static_cast<void>(i);  // read only when gated: clang warns of an unused capture otherwise
    });
  }
}

// Each voxel's hit points, in point order: a counting sort of hits_ by voxel.
inline void ScanEventRecorder::groupHitPoints(ScanEvents& out) {
  // markHits runs before any ray: the voxels with hits are the first hit_voxels_ touched. A hash table of their
  // cells, open addressing, at most half full, maps each hit's cell to its voxel (a binary search over the sorted
  // cells was 5 % of a k-NN build).
  std::size_t size = 16;
  while (size < 2 * std::size_t(hit_voxels_)) size *= 2;
  const int shift = 64 - std::countr_zero(size);
  const std::size_t mask = size - 1;
  const auto slotOf = [&](std::uint32_t cell) { return std::size_t((cell * 0x9E3779B97F4A7C15ull) >> shift); };
  hit_slots_.assign(size, {kNoCell, 0});
  for (std::uint32_t v = 0; v < hit_voxels_; ++v) {
    std::size_t s = slotOf(touched_[v]);
    while (hit_slots_[s].first != kNoCell) s = (s + 1) & mask;
    hit_slots_[s] = {touched_[v], v};
  }
  for (auto& h : hits_) {
    std::size_t s = slotOf(h.first);
    while (hit_slots_[s].first != h.first) s = (s + 1) & mask;
    h.first = hit_slots_[s].second;
  }
  for (const auto& [v, j] : hits_) ++out.voxels[v].hit_count;
  std::uint32_t offset = 0;
  for (std::uint32_t v = 0; v < hit_voxels_; ++v) {
    out.voxels[v].first_hit = offset;
    offset += out.voxels[v].hit_count;
    out.voxels[v].hit_count = 0;
  }
  out.hit_points.resize(offset);
  for (const auto& [v, j] : hits_) out.hit_points[out.voxels[v].first_hit + out.voxels[v].hit_count++] = j;
}

inline void ScanEventRecorder::record(const Scan& scan, const std::vector<std::uint32_t>& inner, double s_c,
                                      const KeyWindow& window, ScanEvents& out, const GateScores& scores) {
  recordIn(scan, inner, s_c, window, out, scores, RayTest::MayReach);
}

inline void ScanEventRecorder::recordIn(const Scan& scan, const std::vector<std::uint32_t>& inner, double s_c,
                                        const KeyWindow& window, ScanEvents& out, const GateScores& scores,
                                        RayTest test) {
  out.voxels.clear();
  out.hit_points.clear();
  out.extremes.clear();
  scores_ = scores.empty() ? nullptr : &scores;
  const std::uint16_t stamp = startScan(window);
  if (scores_ && slot_.size() < window.volume()) slot_.resize(window.volume());
  extremes_.clear();
  markHits(scan, inner, window, stamp);
  hit_voxels_ = std::uint32_t(touched_.size());
  if (scores_)
    markRays<true>(scan, s_c, window, stamp, test);
  else
    markRays<false>(scan, s_c, window, stamp, test);
  if (scores_) out.extremes.swap(extremes_);
  scores_ = nullptr;
  // One event per touched cell, in first-touch order; hit points grouped per voxel in point order.
  out.voxels.reserve(touched_.size());
  for (std::uint32_t cell : touched_)
    out.voxels.push_back(VoxelEvent{window.key(cell), std::uint8_t(cells_[cell] & 0xFF), 0, 0});
  if (!hits_.empty()) groupHitPoints(out);
}

}  // namespace occsweep
