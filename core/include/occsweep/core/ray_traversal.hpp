// Our own ray traversal: liboctomap's computeRayKeys (Amanatides-Woo 3D DDA) re-written step for step with the
// same float and double operations, so it visits exactly the same keys in the same order, but calls `visit`
// instead of filling a KeyRay, and can stop early. tests/core/test_ray_traversal.cpp checks it key for key against
// liboctomap on millions of random rays.
#pragma once

#include <cmath>
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

// ---------------------------------------------------------------------------------------------------------

template <class Visit>
bool traverseRay(const octomap::OcTree& grid, const octomap::point3d& origin, const octomap::point3d& end,
                 Visit&& visit) {
  octomap::OcTreeKey key_origin, key_end;
  if (!grid.coordToKeyChecked(origin, key_origin) || !grid.coordToKeyChecked(end, key_end)) return false;
  if (key_origin == key_end) return true;
  auto keepGoing = [&](const octomap::OcTreeKey& k) {
    if constexpr (std::is_same_v<decltype(visit(k)), bool>) return visit(k);
    else return visit(k), true;
  };
  if (!keepGoing(key_origin)) return true;

  // Initialisation, as OcTreeBaseImpl::computeRayKeys: direction and length in float, tMax/tDelta in double.
  octomap::point3d direction = (end - origin);
  const float length = (float)direction.norm();
  direction /= length;
  const double resolution = grid.getResolution();
  int step[3];
  double t_max[3], t_delta[3];
  const octomap::OcTreeKey& current = key_origin;
  for (unsigned i = 0; i < 3; ++i) {
    if (direction(i) > 0.0) step[i] = 1;
    else if (direction(i) < 0.0) step[i] = -1;
    else step[i] = 0;
    if (step[i] != 0) {
      double border = grid.keyToCoord(current[i]);
      border += (float)(step[i] * resolution * 0.5);
      t_max[i] = (border - origin(i)) / direction(i);
      t_delta[i] = resolution / std::fabs(direction(i));
    } else {
      t_max[i] = std::numeric_limits<double>::max();
      t_delta[i] = std::numeric_limits<double>::max();
    }
  }
  // Incremental phase: liboctomap's loop with its state in registers. liboctomap picks
  //   if (t0 < t1) dim = t0 < t2 ? 0 : 2; else dim = t1 < t2 ? 1 : 2;
  // the selects below give the same dim for every input (ties included), then only t_max[dim] grows.
  double t0 = t_max[0], t1 = t_max[1], t2 = t_max[2];
  const double d0 = t_delta[0], d1 = t_delta[1], d2 = t_delta[2];
  int k0 = current[0], k1 = current[1], k2 = current[2];
  const int e0 = key_end[0], e1 = key_end[1], e2 = key_end[2];
  while (true) {
    const bool first_is_1 = t1 <= t0;
    const double t_first = first_is_1 ? t1 : t0;
    const bool pick2 = !(t_first < t2);
    const bool pick1 = first_is_1 && !pick2, pick0 = !first_is_1 && !pick2;
    k0 += pick0 ? step[0] : 0;
    k1 += pick1 ? step[1] : 0;
    k2 += pick2 ? step[2] : 0;
    t0 = pick0 ? t0 + d0 : t0;
    t1 = pick1 ? t1 + d1 : t1;
    t2 = pick2 ? t2 + d2 : t2;
    // key_type is 16 bits: wrap like current[dim] += step[dim] does
    k0 &= 0xFFFF, k1 &= 0xFFFF, k2 &= 0xFFFF;
    if (k0 == e0 && k1 == e1 && k2 == e2) return true;
    if (std::min(std::min(t0, t1), t2) > length) return true;
    if (!keepGoing(octomap::OcTreeKey(octomap::key_type(k0), octomap::key_type(k1), octomap::key_type(k2))))
      return true;
  }
}

}  // namespace occsweep
