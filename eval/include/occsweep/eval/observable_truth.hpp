// Observable truth (docs/results-format.md, "Truth"): the truth voxels a sensor of the data set could have seen.
// A truth voxel is observable when a ray from some scan origin to its centre or to the centre of one of its faces
// (a hundredth of a voxel inside), that point inside the scan's view (core/sensor_view.hpp) and the voxel's centre
// within s_c, reaches it before it crosses any other truth voxel. Rays are cast against the truth itself (not the
// measured points), at the truth's resolution, with OctoMap's ray keys (traverseRay: origin voxel included, end
// voxel excluded).
#pragma once

#include <string>
#include <vector>

#include <octomap/octomap_types.h>

#include "occsweep/core/enum_names.hpp"
#include "occsweep/core/point_cloud_set.hpp"
#include "occsweep/core/sensor_view.hpp"
#include "ground_truth.hpp"
#include "truth_mask.hpp"

namespace occsweep {

/// Which truth voxels an evaluation counts: all of them (the paper's, the default), or only the observable ones;
/// the others leave the evaluation (neither positive nor negative).
enum class TruthMode { Full, Observable };

/// The names of the modes in results files (map.truth) and on the command line (--truth; .list() for CLI11's
/// IsMember).
inline constexpr EnumNames<TruthMode, 2> kTruthModeNames{
    "truth", {{{TruthMode::Full, "full"}, {TruthMode::Observable, "observable"}}}};

/// "full" or "observable".
[[nodiscard]] const char* truthModeName(TruthMode mode);

/// The mode of that name; throws std::invalid_argument naming the value and the two accepted names.
[[nodiscard]] TruthMode parseTruthMode(const std::string& name);

/// Where a scan was taken from and what its sensor could see from there.
struct Viewpoint {
  octomap::point3d origin;
  SensorView view = SphereView{};
};

/// The truth voxels (of truth.occupied) observable from `viewpoints` with maximum range `s_c` (metres): a voxel
/// whose centre lies within s_c of a viewpoint's origin ((centre - origin).norm() <= s_c, as OctoMap's maxrange
/// test), and whose ray from that origin to its centre, or to one of its six face centres moved a hundredth of a
/// voxel inwards, visits no truth voxel (a surface seen at a grazing angle counts), that aim point lying inside the
/// viewpoint's view (inView). An origin lying in a truth voxel sees that voxel whatever its view (a ray inside one
/// voxel visits nothing; no direction to test) and nothing else (its own voxel, the ray's first key, blocks).
/// Only the truth voxels of `truth` (those inside its region) block; an origin outside OctoMap's key range sees
/// nothing. Cost: at most viewpoints x truth voxels rays of at most s_c / resolution steps each.
[[nodiscard]] octomap::KeySet observableTruthVoxels(const GroundTruth& truth, const std::vector<Viewpoint>& viewpoints,
                                                    double s_c);

/// Those of `candidates` (truth voxels of `mask`, at `resolution`) that are observable by the same rule, every truth
/// voxel blocking: what a sample of the truth costs (truth_coverage.hpp).
[[nodiscard]] std::vector<octomap::OcTreeKey> observableAmong(const TruthMask& mask, double resolution,
                                                              const std::vector<octomap::OcTreeKey>& candidates,
                                                              const std::vector<Viewpoint>& viewpoints, double s_c);

/// The same, every origin seeing in every direction (SphereView): the rule for scans that record no view.
[[nodiscard]] octomap::KeySet observableTruthVoxels(const GroundTruth& truth,
                                                    const std::vector<octomap::point3d>& origins, double s_c);

/// `truth` with its unobservable voxels in `excluded`, so that every evaluation leaves them out.
[[nodiscard]] GroundTruth restrictToObservable(GroundTruth truth, const std::vector<Viewpoint>& viewpoints, double s_c);

/// Each scan's origin and view; a scan that records no view (a data set written before views were) sees in every
/// direction, as observable truth counted before views were recorded.
[[nodiscard]] std::vector<Viewpoint> viewpointsOf(const PointCloudSet& set);

/// The truth an evaluation in `mode` counts: `full` as it is, or restricted to what the scans observe. Under
/// observable truth, scans without a view get a warning on stderr, once per `dataset` (its folder, as the user
/// named it) in this process.
[[nodiscard]] GroundTruth evaluatedTruth(TruthMode mode, GroundTruth full, const PointCloudSet& set, double s_c,
                                         const std::string& dataset);

}  // namespace occsweep
