// `occsweep dataset middlebury`: a real stereo pair with ground-truth disparity from the Middlebury 2006
// data sets (Hirschmüller and Scharstein, CVPR 2007) turned into occsweep data sets, with the rendered sets' SGBM
// settings, reprojection and voxel filter. Camera model and sources: docs/datasets.md, "Real stereo: Middlebury".
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "occsweep/eval/dataset.hpp"
#include "occsweep/eval/confusion.hpp"
#include "camera.hpp"
#include "pointcloud_grid.hpp"
#include "render.hpp"
#include "sgbm.hpp"

namespace occsweep::stereo {

/// Where Debian's opencv-doc package installs OpenCV's sample data (aloeL.jpg, aloeR.jpg, aloeGT.png).
inline const std::filesystem::path kOpenCvSampleData = "/usr/share/doc/opencv-doc/examples/data";

/// The 2005 and 2006 sets' calibration: Z = f B / (d + doffs), d the full-size disparity in pixels.
struct MiddleburyCamera {
  double focal_px = 3740.0;  ///< full-size images
  double baseline_m = 0.160; ///< between views 1 and 5
  double doffs_px = 270.0;   ///< Aloe's dmin.txt: the images were cropped, shifting every disparity by dmin
};

/// A rectified pair as 8-bit grey images and its ground truth: full-size disparity in pixels, 0 = unknown.
struct MiddleburyPair {
  GreyImage left, right;
  std::vector<std::uint8_t> truth_disparity;  ///< row-major, the left image's size
};

/// Reads the two JPEG (or 8-bit PNG) images as grey (libjpeg's luma) and the 8-bit PNG ground truth. DataError
/// naming the file for a missing or unreadable file, colour ground truth, or sizes that differ.
[[nodiscard]] MiddleburyPair readMiddleburyPair(const std::filesystem::path& left, const std::filesystem::path& right,
                                                const std::filesystem::path& truth);

/// The occsweep camera of a pair this size: fx = focal, principal point at the image centre (the sets publish no
/// principal point; it moves points sideways only, and truth and clouds alike), baseline B.
[[nodiscard]] StereoCamera middleburyStereoCamera(const MiddleburyCamera& camera, int width, int height);

/// Disparities in OpenCV's fixed point (1/16 px) with doffs added to the valid ones (> 0), so that
/// reprojectDisparity's z = fx B / d is the data set's Z = f B / (d + doffs). Invalid ones stay as they are.
/// Throws std::invalid_argument when a sum leaves the 16-bit fixed point (2048 px).
[[nodiscard]] std::vector<std::int16_t> withDisparityOffset(const std::vector<std::int16_t>& disparity, double doffs_px);

/// The ground truth's points (each known pixel reprojected with the camera model, left camera at the origin).
[[nodiscard]] std::vector<Eigen::Vector3d> truthPoints(const MiddleburyPair& pair, const MiddleburyCamera& camera);

/// Truth sources for `leaf`: the centre of every voxel (floor(p / leaf)) holding a truth point, so that any key
/// arithmetic puts each in the same voxel; ordered by (z, y, x).
[[nodiscard]] TruthSources voxelCentreTruth(const std::vector<Eigen::Vector3d>& points, double leaf);

/// The smallest multiple of 16 above the largest ground-truth disparity: SGBM searches 0 .. numDisparities - 1.
[[nodiscard]] int numDisparitiesCovering(const MiddleburyPair& pair);

/// The point cloud parameter ids of the pair's sets: the ci scale's even subset of `grid`, as generate uses
/// (the first, the middle and the last combination of the 1,600).
[[nodiscard]] std::vector<std::uint64_t> middleburyPointCloudIds(const PointCloudGrid& grid);

struct MiddleburySetSummary {
  std::uint64_t points = 0;             ///< after the voxel filter (if any)
  std::uint64_t truth_pixels = 0;       ///< pixels with a known disparity
  double valid_fraction = 0;            ///< of those, with a valid SGBM disparity
  double bad1_fraction = 0;             ///< of the valid ones, |SGBM - truth| > 1 px (Middlebury's "bad 1.0")
  ConfusionCounts naive;                ///< filtered points against the truth voxels
};

/// The voxel sizes of a Middlebury set: the truth's voxels, and whether and at what leaf the clouds are
/// voxel-filtered (`dataset middlebury --leaf L [--voxel-filter F | --no-voxel-filter]`: docs/datasets.md).
struct MiddleburyVoxels {
  double leaf = 0.1;         ///< truth voxels, and the sweep's resolution
  bool voxel_filter = true;  ///< false: the raw reprojected points (one per valid disparity)
  double filter_leaf = 0;    ///< the filter's leaf when filtered; 0: `leaf` (one point per truth voxel)

  [[nodiscard]] double filterLeaf() const { return filter_leaf > 0 ? filter_leaf : leaf; }
};

/// One point cloud set: SGBM with `params` and `num_disparities`, doffs added, reprojected (max depth 20 m as the
/// rendered sets), voxel-filtered at `voxels.filterLeaf()` unless `voxels.voxel_filter` is false; one scan from the
/// origin; truth and region (truthRegion) from the GT at `voxels.leaf`. `source` records the camera, the SGBM block
/// as generate's sourceJson does and the filter (name, id and grid: the caller's).
[[nodiscard]] Dataset middleburyDataset(const MiddleburyPair& pair, const MiddleburyCamera& camera,
                                        const SgbmParams& params, int num_disparities, const MiddleburyVoxels& voxels,
                                        MiddleburySetSummary* summary = nullptr);

/// The same, voxel-filtered at `leaf` (the default of `dataset middlebury`).
[[nodiscard]] inline Dataset middleburyDataset(const MiddleburyPair& pair, const MiddleburyCamera& camera,
                                               const SgbmParams& params, int num_disparities, double leaf,
                                               MiddleburySetSummary* summary = nullptr) {
  return middleburyDataset(pair, camera, params, num_disparities, MiddleburyVoxels{leaf, true}, summary);
}

}  // namespace occsweep::stereo
