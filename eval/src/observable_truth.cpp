#include "occsweep/eval/observable_truth.hpp"

#include <algorithm>
#include <array>
#include <iostream>
#include <mutex>
#include <set>
#include <stdexcept>

#include <octomap/OcTree.h>

#include "occsweep/core/ray_traversal.hpp"
#include "occsweep/eval/truth_mask.hpp"

namespace occsweep {
namespace {

// Where a ray may aim in a voxel: its centre and the centres of its six faces, moved a hundredth of a voxel inwards
// so that they stay in it. Aiming at the centre alone hides a surface seen at a grazing angle behind its own
// neighbours: the cameras see the boxes' tops at about 15 degrees, and below 45 degrees a ray to a top voxel's
// centre crosses the next top voxel first (docs/results-format.md, "Truth").
std::array<octomap::point3d, 7> aimPoints(const octomap::point3d& centre, double resolution) {
  const float d = float((0.5 - 0.01) * resolution);
  std::array<octomap::point3d, 7> p;
  p.fill(centre);
  for (int axis = 0; axis < 3; ++axis) p[1 + 2 * axis](axis) += d, p[2 + 2 * axis](axis) -= d;
  return p;
}

// True when a ray from the viewpoint's origin to one of the aim points of `key` that lies in its view visits no
// truth voxel, the voxel's centre lying within s_c of the origin. The origin's own voxel needs no view: the ray
// inside it visits nothing and has no direction (docs/results-format.md, "Truth").
bool seenFrom(const octomap::OcTree& grid, const TruthMask& mask, const Viewpoint& from, const octomap::OcTreeKey& key,
              double s_c) {
  const octomap::point3d& origin = from.origin;
  const octomap::point3d centre = grid.keyToCoord(key);
  if (!(double((centre - origin).norm()) <= s_c)) return false;
  const bool inside_voxel = grid.coordToKey(origin) == key;
  for (const octomap::point3d& aim : aimPoints(centre, grid.getResolution())) {
    if (grid.coordToKey(aim) != key) continue;  // float rounding at a far coordinate: not this voxel's point
    if (!inside_voxel && !inView(from.view, origin, aim)) continue;
    bool blocked = false;
    const bool traversed = traverseRay(grid, origin, aim, [&](const octomap::OcTreeKey& k) {
      blocked = mask.has(k);
      return !blocked;
    });
    if (traversed && !blocked) return true;
  }
  return false;
}

// Scans without a view fall back to every direction; saying so once per data set keeps a sweep of many grids, or a
// reproduction of many data sets, from repeating it.
void warnOnceWithoutViews(const PointCloudSet& set, const std::string& dataset) {
  const auto viewless = std::count_if(set.begin(), set.end(), [](const Scan& s) { return !s.view; });
  if (viewless == 0) return;
  static std::mutex mutex;
  static std::set<std::string> warned;
  const std::lock_guard<std::mutex> lock(mutex);
  if (!warned.insert(dataset).second) return;
  std::cerr << "occsweep: warning: " << dataset << ": " << viewless << " of " << set.size()
            << " scans record no sensor view (a data set written before views were recorded: docs/dataset-format.md, "
               "\"Sensor views\"); observable truth counts what their origins see in every direction, as before\n";
}

}  // namespace

const char* truthModeName(TruthMode mode) { return kTruthModeNames.text(mode); }

TruthMode parseTruthMode(const std::string& name) { return kTruthModeNames.parse(name); }

octomap::KeySet observableTruthVoxels(const GroundTruth& truth, const std::vector<Viewpoint>& viewpoints,
                                      double s_c) {
  const std::vector<octomap::OcTreeKey> all(truth.occupied.begin(), truth.occupied.end());
  const std::vector<octomap::OcTreeKey> seen =
      observableAmong(TruthMask(truth.occupied), truth.resolution, all, viewpoints, s_c);
  return {seen.begin(), seen.end()};
}

std::vector<octomap::OcTreeKey> observableAmong(const TruthMask& mask, double resolution,
                                                const std::vector<octomap::OcTreeKey>& candidates,
                                                const std::vector<Viewpoint>& viewpoints, double s_c) {
  std::vector<octomap::OcTreeKey> seen;
  if (mask.count() == 0) return seen;
  const octomap::OcTree grid(resolution);
  for (const auto& key : candidates)
    if (std::any_of(viewpoints.begin(), viewpoints.end(),
                    [&](const Viewpoint& from) { return seenFrom(grid, mask, from, key, s_c); }))
      seen.push_back(key);
  return seen;
}

octomap::KeySet observableTruthVoxels(const GroundTruth& truth, const std::vector<octomap::point3d>& origins,
                                      double s_c) {
  std::vector<Viewpoint> all_round;
  for (const auto& origin : origins) all_round.push_back({origin, SphereView{}});
  return observableTruthVoxels(truth, all_round, s_c);
}

GroundTruth restrictToObservable(GroundTruth truth, const std::vector<Viewpoint>& viewpoints, double s_c) {
  const octomap::KeySet seen = observableTruthVoxels(truth, viewpoints, s_c);
  truth.excluded.clear();
  for (const auto& key : truth.occupied)
    if (!seen.count(key)) truth.excluded.insert(key);
  return truth;
}

std::vector<Viewpoint> viewpointsOf(const PointCloudSet& set) {
  std::vector<Viewpoint> viewpoints;
  viewpoints.reserve(set.size());
  for (const Scan& scan : set) viewpoints.push_back({scan.origin, scan.view.value_or(SphereView{})});
  return viewpoints;
}

GroundTruth evaluatedTruth(TruthMode mode, GroundTruth full, const PointCloudSet& set, double s_c,
                           const std::string& dataset) {
  if (mode == TruthMode::Full) return full;
  warnOnceWithoutViews(set, dataset);
  return restrictToObservable(std::move(full), viewpointsOf(set), s_c);
}

}  // namespace occsweep
