#include "occsweep/eval/truth_coverage.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <tuple>

#include <octomap/OcTree.h>

#include "occsweep/eval/truth_mask.hpp"

namespace occsweep {
namespace {

bool inRegion(const octomap::OcTree& grid, const GroundTruth& frame, const octomap::point3d& p) {
  octomap::OcTreeKey at;
  return grid.coordToKeyChecked(p, at) && frame.inRegion(at);
}

// The points inside the region, kCoveragePointSample of them evenly spaced in scan order (all when fewer); counts
// them into `c`. Points outside are left out: the truth beyond a --region is not rasterised.
std::vector<octomap::point3d> sampledRegionPoints(const octomap::OcTree& grid, const GroundTruth& frame,
                                                  const PointCloudSet& scans, TruthCoverage& c) {
  for (const Scan& scan : scans)
    for (const auto& p : scan.points) c.points_in_region += inRegion(grid, frame, p);
  const std::vector<std::size_t> at = evenlySpaced(c.points_in_region, kCoveragePointSample);
  std::vector<octomap::point3d> sample;
  std::size_t ordinal = 0;  // of the point among those in the region
  for (const Scan& scan : scans)
    for (const auto& p : scan.points)
      if (sample.size() < at.size() && inRegion(grid, frame, p) && ordinal++ == at[sample.size()]) sample.push_back(p);
  return sample;
}

// The distance from `p` to the nearest truth voxel centre, looked for shell by shell (the keys r voxels away in
// the largest axis) up to kPointSearchVoxels: a voxel of shell r + 1 lies at least r + 0.5 voxels away.
double nearestTruthDistance(const octomap::OcTree& grid, const TruthMask& truth, const octomap::OcTreeKey& at,
                            const octomap::point3d& p) {
  const double resolution = grid.getResolution(), cap = (kPointSearchVoxels + 0.5) * resolution;
  double best = cap;
  for (int r = 0; r <= kPointSearchVoxels && best > (r - 0.5) * resolution; ++r)
    for (int dx = -r; dx <= r; ++dx)
      for (int dy = -r; dy <= r; ++dy) {
        const bool side = std::abs(dx) == r || std::abs(dy) == r;
        for (int dz = -r; dz <= r; dz += side ? 1 : std::max(1, 2 * r)) {
          const int c[3] = {at[0] + dx, at[1] + dy, at[2] + dz};
          if (std::any_of(c, c + 3, [](int v) { return v < 0 || v > 65535; })) continue;
          const octomap::OcTreeKey key{std::uint16_t(c[0]), std::uint16_t(c[1]), std::uint16_t(c[2])};
          if (truth.has(key)) best = std::min(best, double((grid.keyToCoord(key) - p).norm()));
        }
      }
  return best;
}

double median(std::vector<double> v) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  const std::size_t h = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(h), v.end());
  if (v.size() % 2) return v[h];
  return (v[h] + *std::max_element(v.begin(), v.begin() + std::ptrdiff_t(h))) / 2;
}

std::string percent(double share) {
  std::ostringstream s;
  s << std::lround(100 * share) << " %";
  return s.str();
}

std::string distanceText(const TruthCoverage& c) {
  std::ostringstream s;
  s.precision(2);
  if (c.median_point_distance >= (kPointSearchVoxels + 0.5) * c.resolution) s << "at least ";  // the search's bound
  s << std::fixed << c.median_point_distance << " m (" << std::setprecision(1)
    << c.median_point_distance / c.resolution << " voxels)";
  return s.str();
}

// "78 % of them within a voxel of the truth's surface, 31 % moved by the best offset (+1.50, +0.00, -0.10) m".
std::string offsetText(const OffsetFit& f) {
  std::ostringstream s;
  s << percent(f.share_on_surface) << " of them within a voxel of the truth's surface, "
    << percent(f.offset_share_on_surface) << " moved by the best offset (" << std::showpos << std::fixed
    << std::setprecision(2) << f.offset[0] << ", " << f.offset[1] << ", " << f.offset[2] << ") m";
  return s.str();
}

bool offsetFitsBetter(const TruthCoverage& c) {
  if (!c.offset_fit || c.sampled_points < kOffsetMinPoints) return false;
  const double gain = c.offset_fit->offset_share_on_surface - c.offset_fit->share_on_surface;
  return gain >= kOffsetGainShare && gain >= kOffsetMisfitShare * (1 - c.offset_fit->share_on_surface);
}

// A shift first: as likely as the other convention, whatever the warning's numbers (docs/import.md, "Truth coverage
// and alignment").
constexpr const char* kAlignmentFix =
    "likely causes: the truth or the poses shifted (a pose error, or the truth in another frame), poses written world "
    "to camera (import with --pose-convention world-to-camera), or a wrong --depth-scale (docs/import.md, \"Truth "
    "coverage and alignment\")";

// Of `keys`, those some point of `scans` falls in: each point looked up among the sampled keys, so memory stays
// the sample's, not the points' voxels.
std::uint64_t holdingAPoint(const octomap::OcTree& grid, const std::vector<octomap::OcTreeKey>& keys,
                            const PointCloudSet& scans) {
  const octomap::KeySet sampled(keys.begin(), keys.end());
  octomap::KeySet held;
  for (const Scan& scan : scans)
    for (const auto& p : scan.points)
      if (octomap::OcTreeKey k; grid.coordToKeyChecked(p, k) && sampled.count(k)) held.insert(k);
  return held.size();
}

// The coverage of the truth `mask` holds, in `frame`'s region and at its resolution.
TruthCoverage measureTruthCoverage(const GroundTruth& frame, const TruthMask& mask, const PointCloudSet& scans,
                                   double s_c) {
  TruthCoverage c;
  c.resolution = frame.resolution, c.s_c = s_c;
  c.truth_voxels = mask.count();
  const std::vector<octomap::OcTreeKey> keys = mask.evenSample(kCoverageTruthSample);
  c.sampled_truth = keys.size();
  c.observable_sampled = observableAmong(mask, frame.resolution, keys, viewpointsOf(scans), s_c).size();
  const octomap::OcTree grid(frame.resolution);
  c.with_point_sampled = holdingAPoint(grid, keys, scans);
  c.points = pointCount(scans);
  std::vector<double> distances;
  const std::vector<octomap::point3d> points = sampledRegionPoints(grid, frame, scans, c);
  for (const octomap::point3d& p : points) distances.push_back(nearestTruthDistance(grid, mask, grid.coordToKey(p), p));
  c.sampled_points = distances.size();
  c.median_point_distance = median(std::move(distances));
  if (!points.empty()) c.offset_fit = bestOffset(mask, frame.resolution, points);
  return c;
}

}  // namespace

double TruthCoverage::observableShare() const {
  return sampled_truth ? double(observable_sampled) / double(sampled_truth) : std::numeric_limits<double>::quiet_NaN();
}

double TruthCoverage::withPointShare() const {
  return sampled_truth && with_point_sampled ? double(*with_point_sampled) / double(sampled_truth)
                                             : std::numeric_limits<double>::quiet_NaN();
}

TruthCoverage measureTruthCoverage(const GroundTruth& truth, const PointCloudSet& scans, double s_c) {
  return measureTruthCoverage(truth, TruthMask(truth.occupied), scans, s_c);
}

TruthCoverage measureTruthCoverage(const TruthSources& sources, const AxisBox& region, double resolution,
                                   const PointCloudSet& scans, double s_c) {
  const GroundTruth frame = makeGroundTruth({}, region, resolution);
  return measureTruthCoverage(frame, TruthMask(sources, frame), scans, s_c);
}

std::string coverageText(const TruthCoverage& c) {
  std::ostringstream s;
  s << "truth coverage at " << c.resolution << " m, s_c " << c.s_c << " m: " << percent(c.observableShare())
    << " of the truth voxels observable from the scans (" << c.observable_sampled << " of " << c.sampled_truth
    << " sampled of " << c.truth_voxels << ")";
  if (c.with_point_sampled) s << ", " << percent(c.withPointShare()) << " holding a point";
  s << "; ";
  if (c.points_in_region == 0) return s.str() + "no point in the region";
  s << "median distance from the points to the nearest truth voxel " << distanceText(c) << ", over "
    << c.sampled_points << " sampled of the " << c.points_in_region << " points in the region (of " << c.points
    << ")";
  if (c.offset_fit) s << "; " << offsetText(*c.offset_fit);
  return s.str();
}

std::string coverageWarning(const TruthCoverage& c, TruthMode mode) {
  // Misaligned, the share measures the misalignment too: the fix is the poses or the truth, not observable truth.
  if (c.points_in_region == 0)
    return "none of the " + std::to_string(c.points) + " points lies in the region: scans and truth are not " +
           "aligned; " + kAlignmentFix;
  const std::string offset = offsetFitsBetter(c) ? "of the points, " + offsetText(*c.offset_fit) +
                                                      ": one translation fits them clearly better than none"
                                                    : "";
  const bool far = !(c.median_point_distance <= kFarPointVoxels * c.resolution);
  if (far || !offset.empty())  // the distance too when an offset fits: past the search's reach, that offset is partial
    return "the points lie a median " + distanceText(c) + " from the nearest truth voxel" +
           (far ? " (more than " + std::to_string(int(kFarPointVoxels)) + " voxels)" : "") +
           (offset.empty() ? "" : "; " + offset) + ": scans and truth are not aligned; " + kAlignmentFix;
  if (mode != TruthMode::Full || !(c.observableShare() < kLowObservableShare) ||
      c.withPointShare() >= kLowObservableShare)  // NaN (not measured): the observable share decides
    return "";
  const std::string held = c.with_point_sampled ? " and " + percent(c.withPointShare()) + " hold a point" : "";
  std::string text = "only " + percent(c.observableShare()) + " of the truth voxels are observable from the scans" +
                     held + " (below " + percent(kLowObservableShare) + "): under full truth every map misses " +
                     "most of the rest, so its AUC measures the recording's coverage, not the mapping; sweep with " +
                     "--truth observable, or import truth with a --region around what the recording sees";
  if (c.offset_fit && c.offset_fit->share_on_surface < kOffSurfacePointShare)  // a shift past the offset search
    return text + "; unless scans and truth are not aligned (only " + percent(c.offset_fit->share_on_surface) +
           " of the points lie within a voxel of the truth's surface): " + kAlignmentFix;
  return text + " (docs/import.md, \"Truth coverage and alignment\")";
}

}  // namespace occsweep
