// Our own ray traversal: liboctomap's computeRayKeys (Amanatides-Woo 3D DDA) re-written step for step with the
// same float and double operations, so it visits exactly the same keys in the same order, but calls `visit`
// instead of filling a KeyRay, and can stop early. tests/core/test_ray_traversal.cpp checks it key for key against
// liboctomap on millions of random rays, and traverseRayInWindow against traverseRay's keys filtered by the box.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>

#include <octomap/OcTree.h>

namespace occsweep {

/// Visits the keys liboctomap's computeRayKeys(origin, end) would return: the origin voxel first, the end voxel
/// excluded; nothing when both lie in one voxel. Returns false (visiting nothing) when an end is outside the
/// octree, as computeRayKeys does. `visit(key)` may return bool: false stops the ray there.
template <class Visit>
bool traverseRay(const octomap::OcTree& grid, const octomap::point3d& origin, const octomap::point3d& end,
                 Visit&& visit);

/// An inclusive box of keys: per axis [lo, hi] (the voxels a scan's events are kept for, the evaluation region).
struct KeyWindow {
  std::array<int, 3> lo{}, hi{};
  [[nodiscard]] bool contains(const octomap::OcTreeKey& k) const {
    return k[0] >= lo[0] && k[0] <= hi[0] && k[1] >= lo[1] && k[1] <= hi[1] && k[2] >= lo[2] && k[2] <= hi[2];
  }
  /// In 64 bits: a window of 65536^3 keys does not fit 32 (a wrapped volume would crash k-NN maps).
  [[nodiscard]] std::uint64_t volume() const {
    return std::uint64_t(hi[0] - lo[0] + 1) * std::uint64_t(hi[1] - lo[1] + 1) * std::uint64_t(hi[2] - lo[2] + 1);
  }
  [[nodiscard]] std::uint64_t index(const octomap::OcTreeKey& k) const {
    return (std::uint64_t(k[0] - lo[0]) * std::uint64_t(hi[1] - lo[1] + 1) + std::uint64_t(k[1] - lo[1])) *
               std::uint64_t(hi[2] - lo[2] + 1) + std::uint64_t(k[2] - lo[2]);
  }
  /// The key of an index of this window (the inverse of index).
  [[nodiscard]] octomap::OcTreeKey key(std::uint64_t index) const {
    const auto nz = std::uint64_t(hi[2] - lo[2] + 1), ny = std::uint64_t(hi[1] - lo[1] + 1);
    return octomap::OcTreeKey(octomap::key_type(lo[0] + int(index / (ny * nz))),
                              octomap::key_type(lo[1] + int(index / nz % ny)),
                              octomap::key_type(lo[2] + int(index % nz)));
  }
};

/// Visits, in order, exactly the keys of traverseRay(grid, origin, end) that lie in `window`, as
/// visit(window.index(key)) (window.key gives the key back); returns what traverseRay returns. A ray's keys move
/// monotonically along each axis, so those in a box are one run: the keys before it are skipped without stepping
/// through them (docs/performance.md, "Skipping to the window"), and the ray stops after it.
template <class Visit>
bool traverseRayInWindow(const octomap::OcTree& grid, const octomap::point3d& origin, const octomap::point3d& end,
                         const KeyWindow& window, Visit&& visit);

// ---------------------------------------------------------------------------------------------------------

namespace detail {

/// computeRayKeys' variables after its initialisation: per axis the ray parameter of the next voxel border
/// (t_max), the distance between borders (t_delta) and the step; the current and the end key; the length.
/// Not initialised here: startRay sets every field of a ray it starts (zeroing 112 bytes for each of millions of
/// rays was an eighth of the k-NN build's per-ray work).
struct RayState {
  std::array<double, 3> t_max, t_delta;
  std::array<int, 3> step, key, end;
  float length;
};

enum class RayStart { OutsideOctree, OneVoxel, Started };

// Initialisation, as OcTreeBaseImpl::computeRayKeys: direction and length in float, tMax/tDelta in double.
inline RayStart startRay(const octomap::OcTree& grid, const octomap::point3d& origin, const octomap::point3d& end,
                         RayState& s) {
  octomap::OcTreeKey key_origin, key_end;
  if (!grid.coordToKeyChecked(origin, key_origin) || !grid.coordToKeyChecked(end, key_end))
    return RayStart::OutsideOctree;
  if (key_origin == key_end) return RayStart::OneVoxel;
  octomap::point3d direction = (end - origin);
  s.length = (float)direction.norm();
  direction /= s.length;
  const double resolution = grid.getResolution();
  for (unsigned i = 0; i < 3; ++i) {
    s.key[i] = key_origin[i];
    s.end[i] = key_end[i];
    if (direction(i) > 0.0) s.step[i] = 1;
    else if (direction(i) < 0.0) s.step[i] = -1;
    else s.step[i] = 0;
    if (s.step[i] != 0) {
      double border = grid.keyToCoord(key_origin[i]);
      border += (float)(s.step[i] * resolution * 0.5);
      s.t_max[i] = (border - origin(i)) / direction(i);
      s.t_delta[i] = resolution / std::fabs(direction(i));
    } else {
      s.t_max[i] = std::numeric_limits<double>::max();
      s.t_delta[i] = std::numeric_limits<double>::max();
    }
  }
  return RayStart::Started;
}

// The incremental phase from s (whose key has been visited): liboctomap's loop with its state in registers.
// liboctomap picks
//   if (t0 < t1) dim = t0 < t2 ? 0 : 2; else dim = t1 < t2 ? 1 : 2;
// the selects below give the same dim for every input (ties included), then only t_max[dim] grows.
// continueRayInWindow repeats these selects: the same lines moved into a function returning the three picks made
// both loops 10 % slower (g++ 12, octomap-opt's recording), so each loop keeps them inline.
template <class KeepGoing>
void continueRay(const RayState& s, KeepGoing&& keepGoing) {
  double t0 = s.t_max[0], t1 = s.t_max[1], t2 = s.t_max[2];
  const double d0 = s.t_delta[0], d1 = s.t_delta[1], d2 = s.t_delta[2];
  int k0 = s.key[0], k1 = s.key[1], k2 = s.key[2];
  const int e0 = s.end[0], e1 = s.end[1], e2 = s.end[2];
  const int s0 = s.step[0], s1 = s.step[1], s2 = s.step[2];
  const double length = s.length;  // the loop compares it as a double: converted once, not at every step
  while (true) {
    const bool first_is_1 = t1 <= t0;
    const double t_first = first_is_1 ? t1 : t0;
    const bool pick2 = !(t_first < t2);
    const bool pick1 = first_is_1 && !pick2, pick0 = !first_is_1 && !pick2;
    k0 += pick0 ? s0 : 0;
    k1 += pick1 ? s1 : 0;
    k2 += pick2 ? s2 : 0;
    t0 = pick0 ? t0 + d0 : t0;
    t1 = pick1 ? t1 + d1 : t1;
    t2 = pick2 ? t2 + d2 : t2;
    // key_type is 16 bits: wrap like current[dim] += step[dim] does
    k0 &= 0xFFFF, k1 &= 0xFFFF, k2 &= 0xFFFF;
    if (k0 == e0 && k1 == e1 && k2 == e2) return;
    if (std::min(std::min(t0, t1), t2) > length) return;
    if (!keepGoing(octomap::OcTreeKey(octomap::key_type(k0), octomap::key_type(k1), octomap::key_type(k2)))) return;
  }
}

// The steps as a merge: every step takes, of the three axes' border sequences t_max, t_max + t_delta, ... (each
// summed one addition at a time, as the loop does), the smallest next border; at equal borders axis 2 before 1
// before 0 (liboctomap's picks above). So after the step that takes border (t, axis), each axis has taken exactly
// its borders that come no later in that order, and the state there follows from each axis's additions alone.
inline bool takenBy(double t, int axis, double t_last, int axis_last) {
  return t < t_last || (t == t_last && axis >= axis_last);
}

enum class Skip { Never, AtOrigin, Skipped, Stepwise };

// Moves s to the state after the step into `box` (Skipped), or leaves it at the origin's key when that is in the
// box (AtOrigin):
//  - per axis, the numbers of its steps that keep its key in [lo, hi]: [first, last];
//  - the step into the box takes the latest of the axes' borders number `first`; every axis then has taken its
//    borders up to that one (takenBy), counted by additions;
//  - none of the skipped keys is in the box, and none was a stop of the loop: a border past the length comes at
//    or after the first border beyond it (checked by the caller at the new state, as the loop would), and the
//    end key, when every axis's count reaches it, may lie on the way (or be the key skipped to): then the caller
//    steps (Stepwise).
// Never: the ray's keys never enter the box.
inline Skip skipToWindow(RayState& s, const KeyWindow& box, std::array<int, 3>& steps_left) {
  constexpr int kFar = std::numeric_limits<int>::max();
  std::array<int, 3> first{}, last{};
  bool at_origin = true;
  for (int i = 0; i < 3; ++i) {
    const int k = s.key[i], st = s.step[i];
    if (st == 0) {
      if (k < box.lo[i] || k > box.hi[i]) return Skip::Never;
      first[i] = 0, last[i] = kFar;
      continue;
    }
    first[i] = std::max(0, st > 0 ? box.lo[i] - k : k - box.hi[i]);
    last[i] = st > 0 ? box.hi[i] - k : k - box.lo[i];
    if (last[i] < 0) return Skip::Never;
    at_origin = at_origin && first[i] == 0;
  }
  if (at_origin) {
    steps_left = last;
    return Skip::AtOrigin;
  }
  // The border whose step brings the last axis into range.
  std::array<int, 3> taken{};
  std::array<double, 3> t = s.t_max;
  double t_entry = -std::numeric_limits<double>::infinity();
  int axis_entry = -1;
  for (int i = 0; i < 3; ++i) {
    if (first[i] == 0) continue;
    for (; taken[i] < first[i] - 1; ++taken[i]) t[i] += s.t_delta[i];
    if (axis_entry < 0 || !takenBy(t[i], i, t_entry, axis_entry)) t_entry = t[i], axis_entry = i;
  }
  for (int i = 0; i < 3; ++i) {
    if (s.step[i] == 0) continue;
    for (; taken[i] <= last[i] && takenBy(t[i], i, t_entry, axis_entry); ++taken[i]) t[i] += s.t_delta[i];
    if (taken[i] > last[i]) return Skip::Never;  // this axis leaves its range before the last one enters
  }
  // The end key on the way: every moving axis's count reaches the end's (axes that do not move stay equal).
  bool end_on_the_way = true;
  for (int i = 0; i < 3; ++i) {
    const int to_end = s.step[i] == 0 ? (s.end[i] == s.key[i] ? 0 : -1) : s.step[i] * (s.end[i] - s.key[i]);
    end_on_the_way = end_on_the_way && to_end >= 0 && to_end <= taken[i];
  }
  if (end_on_the_way) return Skip::Stepwise;
  for (int i = 0; i < 3; ++i) {
    s.key[i] += s.step[i] * taken[i], s.t_max[i] = t[i];
    steps_left[i] = s.step[i] == 0 ? kFar : last[i] - taken[i];
  }
  return Skip::Skipped;
}

// continueRay inside a window, from a key in it: an axis's step leaves the window when that axis has no step left
// in range (steps_left), so no key is compared with the window; the key is kept only as its window index
// (KeyWindow::index), which moves by the axis's stride. Stops, as continueRay, at the end key and past the length:
// inside the window equal indexes are equal keys, and an end key outside it cannot be reached before the ray
// leaves the window (its index is then one no key in the window has). visit(index). Its picks are continueRay's
// (see there why they are written twice).
// `visit` is taken by value: a copy of its own, whose captures no store of the loop can change, stays in registers.
template <class Visit>
void continueRayInWindow(const RayState& s, const std::array<int, 3>& steps_left, const KeyWindow& w, Visit visit) {
  double t0 = s.t_max[0], t1 = s.t_max[1], t2 = s.t_max[2];
  const double d0 = s.t_delta[0], d1 = s.t_delta[1], d2 = s.t_delta[2];
  int left0 = steps_left[0], left1 = steps_left[1], left2 = steps_left[2];
  const auto nz = std::int64_t(w.hi[2] - w.lo[2] + 1), nyz = std::int64_t(w.hi[1] - w.lo[1] + 1) * nz;
  const std::int64_t stride0 = s.step[0] * nyz, stride1 = s.step[1] * nz, stride2 = s.step[2];
  const auto keyOf = [](const std::array<int, 3>& k) {
    return octomap::OcTreeKey(octomap::key_type(k[0]), octomap::key_type(k[1]), octomap::key_type(k[2]));
  };
  std::int64_t index = std::int64_t(w.index(keyOf(s.key)));
  const std::int64_t end_index = w.contains(keyOf(s.end)) ? std::int64_t(w.index(keyOf(s.end))) : -1;
  const double length = s.length;  // the loop compares it as a double: converted once, not at every step
  while (true) {
    const bool first_is_1 = t1 <= t0;
    const double t_first = first_is_1 ? t1 : t0;
    const bool pick2 = !(t_first < t2);
    const bool pick1 = first_is_1 && !pick2, pick0 = !first_is_1 && !pick2;
    left0 -= pick0, left1 -= pick1, left2 -= pick2;
    index += pick0 ? stride0 : (pick1 ? stride1 : stride2);
    t0 = pick0 ? t0 + d0 : t0;
    t1 = pick1 ? t1 + d1 : t1;
    t2 = pick2 ? t2 + d2 : t2;
    if ((left0 | left1 | left2) < 0) return;  // left the window (keys in it are never wrapped)
    if (index == end_index) return;
    if (std::min(std::min(t0, t1), t2) > length) return;
    visit(std::uint64_t(index));
  }
}

}  // namespace detail

template <class Visit>
bool traverseRay(const octomap::OcTree& grid, const octomap::point3d& origin, const octomap::point3d& end,
                 Visit&& visit) {
  detail::RayState s;
  const detail::RayStart start = detail::startRay(grid, origin, end, s);
  if (start != detail::RayStart::Started) return start == detail::RayStart::OneVoxel;
  auto keepGoing = [&](const octomap::OcTreeKey& k) {
    if constexpr (std::is_same_v<decltype(visit(k)), bool>) return visit(k);
    else return visit(k), true;
  };
  if (!keepGoing(octomap::OcTreeKey(octomap::key_type(s.key[0]), octomap::key_type(s.key[1]),
                                    octomap::key_type(s.key[2]))))
    return true;
  detail::continueRay(s, keepGoing);
  return true;
}

template <class Visit>
bool traverseRayInWindow(const octomap::OcTree& grid, const octomap::point3d& origin, const octomap::point3d& end,
                         const KeyWindow& box, Visit&& visit) {
  detail::RayState s;
  const detail::RayStart start = detail::startRay(grid, origin, end, s);
  if (start != detail::RayStart::Started) return start == detail::RayStart::OneVoxel;
  std::array<int, 3> steps_left;  // set by skipToWindow where it is read (AtOrigin, Skipped)
  const detail::Skip skip = detail::skipToWindow(s, box, steps_left);
  switch (skip) {
    case detail::Skip::Never:
      return true;
    case detail::Skip::Stepwise: {  // the plain walk, its keys filtered
      bool entered = false;
      auto filtered = [&](const octomap::OcTreeKey& k) {
        if (!box.contains(k)) return !entered;
        entered = true;
        visit(box.index(k));
        return true;
      };
      if (filtered(octomap::OcTreeKey(octomap::key_type(s.key[0]), octomap::key_type(s.key[1]),
                                      octomap::key_type(s.key[2]))))
        detail::continueRay(s, filtered);
      return true;
    }
    case detail::Skip::AtOrigin:
    case detail::Skip::Skipped:
      break;
  }
  // The loop's length stop after the step into the box (the origin's key has none: it is always visited). Its end
  // key stop cannot come here: a skip to the end key is Stepwise.
  if (skip == detail::Skip::Skipped && std::min({s.t_max[0], s.t_max[1], s.t_max[2]}) > s.length) return true;
  visit(box.index(octomap::OcTreeKey(octomap::key_type(s.key[0]), octomap::key_type(s.key[1]),
                                    octomap::key_type(s.key[2]))));
  detail::continueRayInWindow(s, steps_left, box, visit);
  return true;
}

}  // namespace occsweep
