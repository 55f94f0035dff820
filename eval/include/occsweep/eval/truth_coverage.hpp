// Truth coverage and alignment (docs/import.md, "Truth coverage and alignment"): how much of the truth some scan can
// observe, and how far the measured points lie from it. A recording that sees a tenth of its truth scores coverage,
// not mapping, under full truth; a pose file read in the wrong convention puts every point off the truth. Both
// leave a sweep running and its AUCs meaningless, so import truth, sweep and compare say so, naming the fix.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "occsweep/core/point_cloud_set.hpp"
#include "ground_truth.hpp"
#include "observable_truth.hpp"
#include "truth_offset.hpp"

namespace occsweep {

/// Truth voxels and points measured (bounded cost: evenly spaced samples of each, all of them when fewer).
inline constexpr std::size_t kCoverageTruthSample = 4000, kCoveragePointSample = 2000;
/// Below this share of observable truth voxels, and of truth voxels holding a measured point, full truth measures
/// mostly what the scans could not see: a truth voxel no point falls in is never marked occupied by a map of these
/// points, and one no ray reaches is not seen. Both must be low: a truth made from the scan's own depth at a
/// coarse resolution (Aloe at 0.1 m) holds points in most voxels that a ray at voxel resolution cannot reach.
inline constexpr double kLowObservableShare = 0.3;
/// Below this share of the sampled points within a voxel of the truth's surface, a low share may be misalignment.
inline constexpr double kOffSurfacePointShare = 0.5;
/// Past this median distance from points to the nearest truth voxel centre, in voxels, scans and truth disagree.
inline constexpr double kFarPointVoxels = 2.0;
/// The nearest truth voxel is looked for this many voxels around a point; farther counts as this far (plus half a
/// voxel): a bound that keeps a misaligned recording cheap and is well past kFarPointVoxels.
inline constexpr int kPointSearchVoxels = 8;
/// Scans and truth are not aligned when moving the points by the best offset (truth_offset.hpp) puts at least
/// kOffsetGainShare more of them on the truth's surface, and at least kOffsetMisfitShare of those off it as they
/// are, over at least kOffsetMinPoints sampled points. Aligned, no offset gained more than 0.07, a quarter of the
/// misfit (Aloe's 246 stereo points; the rendered stereo sets and the built-in scene lose with every offset); the
/// depth recording of test_your_own_data with its poses shifted by 0.5 m gains 0.13, four fifths of the misfit.
inline constexpr double kOffsetGainShare = 0.1, kOffsetMisfitShare = 0.5;
inline constexpr std::uint64_t kOffsetMinPoints = 100;

struct TruthCoverage {
  std::uint64_t truth_voxels = 0;       ///< every truth voxel of the region
  std::uint64_t sampled_truth = 0;      ///< truth voxels tested, evenly spaced in key order
  std::uint64_t observable_sampled = 0; ///< of those, observable from some scan (observable_truth.hpp)
  /// Of the sampled truth voxels, those some point of the scans falls in; none in results files written before it
  /// was measured.
  std::optional<std::uint64_t> with_point_sampled;
  std::uint64_t points = 0;             ///< every point of every scan
  std::uint64_t points_in_region = 0;   ///< of those, inside the region (the truth beyond it is not rasterised)
  std::uint64_t sampled_points = 0;     ///< of those, evenly spaced in scan order: the ones measured
  /// Median distance (metres) from the sampled points to the nearest truth voxel centre, at most
  /// (kPointSearchVoxels + 0.5) voxels; NaN when no point lies in the region.
  double median_point_distance = 0;
  /// The best rigid offset of the sampled points (truth_offset.hpp); none when no point lies in the region, or
  /// in results files written before it was measured.
  std::optional<OffsetFit> offset_fit;
  double resolution = 0.1, s_c = 4.0;
  friend bool operator==(const TruthCoverage&, const TruthCoverage&) = default;

  /// observable_sampled / sampled_truth (NaN with no truth).
  [[nodiscard]] double observableShare() const;
  /// with_point_sampled / sampled_truth (NaN with no truth or not measured).
  [[nodiscard]] double withPointShare() const;
};

/// Coverage of `truth` by `scans` with maximum range `s_c`, at the truth's resolution. The truth must not be empty.
[[nodiscard]] TruthCoverage measureTruthCoverage(const GroundTruth& truth, const PointCloudSet& scans, double s_c);

/// The same of the truth `sources` rasterise in `region` at `resolution`, without their key set (truth_mask.hpp):
/// what `import truth` measures. Throws as makeGroundTruth for a bad region or one past the voxel limit.
[[nodiscard]] TruthCoverage measureTruthCoverage(const TruthSources& sources, const AxisBox& region,
                                                 double resolution, const PointCloudSet& scans, double s_c);

/// One line: "truth coverage at 0.1 m, s_c 4 m: 7 % of the truth voxels observable from the scans (269 of 4000
/// sampled of 13132); median distance from the points to the nearest truth voxel 0.07 m (0.7 voxels), over ...".
[[nodiscard]] std::string coverageText(const TruthCoverage& c);

/// What is wrong, naming the fix; "" when nothing is. Scans and truth not aligned (no point in the region, a median
/// distance past kFarPointVoxels, or an offset that fits clearly better, named with the median distance) come first,
/// naming the likely causes: the share then measures the misalignment too.
/// Else an observable share and a share of truth voxels holding a point both below kLowObservableShare, under full
/// truth only (observable truth is the fix), naming misalignment too when few points lie on the truth's surface.
[[nodiscard]] std::string coverageWarning(const TruthCoverage& c, TruthMode mode);

}  // namespace occsweep
