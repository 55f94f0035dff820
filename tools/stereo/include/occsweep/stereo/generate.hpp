// `occsweep dataset generate`: one of the paper's 20 data sets at a scale, one point cloud set per point cloud
// parameter combination, each written as an occsweep data set, ranked by the naive approach's FDR.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "camera.hpp"
#include "pointcloud_grid.hpp"
#include "render.hpp"
#include "scene.hpp"
#include "sgbm.hpp"
#include "occsweep/eval/confusion.hpp"
#include "occsweep/io/output_file.hpp"

namespace occsweep::stereo {

/// How big a reproduction is. `subset` point cloud parameter ids spread evenly over the grid (evenSubset).
struct ScaleConfig {
  std::string name;
  int width = 0, height = 0;
  int keyframes = 0;           ///< over both orbits
  int num_disparities = 0;     ///< SGBM search range: the same 0.65 m minimum depth at every width
  std::uint64_t subset = 0;    ///< point cloud parameter combinations (0: all of the grid)
};

/// ci: 320x180, 24 keyframes, 3 sets; small: 640x360, 48 keyframes, 9 sets; paper: 1280x720, 144, all 1,600.
/// Throws std::invalid_argument for another name.
[[nodiscard]] ScaleConfig scaleConfig(const std::string& name);

/// Which presets of docs/datasets.md "Realism and experiment options" were asked for (recorded, not applied: the
/// caller applies them to the settings below, see realism.hpp).
struct RealismPresets {
  std::string pose_error, exposure;  ///< empty: none (raw knobs, if any, are recorded as numbers)
  bool realistic = false;            ///< --realistic: all realism options at their presets
};

struct GenerateConfig {
  ScaleConfig scale = scaleConfig("ci");
  std::vector<std::uint64_t> pcs_ids;  ///< grid ids; empty: the scale's even subset
  std::optional<SgbmParams> custom;    ///< --sgbm: one set with these settings instead of grid ids
  std::uint64_t seed = 1;              ///< sensor noise and pose drift (mixed with the data set's name)
  PoseDrift drift;                     ///< off by default; its seed is derived from `seed` and the name
  OrbitConfig orbit;                   ///< keyframes are taken from the scale
  RenderConfig render;
  SceneConfig scene;
  double leaf = 0.1;                   ///< voxel filter and ground-truth resolution, metres (Section 4.2)
  bool voxel_filter = true;            ///< --no-voxel-filter: the raw reprojected points (truth stays at `leaf`)
  RealismPresets presets;
  double max_depth = 20.0;             ///< a ZED reports no depth beyond 20 m
  bool preview = true;                 ///< write preview/ PNGs of keyframe 0 (left image, disparities)
  bool progress = true;                ///< progress lines on stderr (`reproduce --quiet` turns them off)
  /// --force: replace occsweep's own earlier output at the data set's names (its sets, ranking, timing, previews);
  /// without it an existing one is refused before any work. A user's file is refused either way.
  bool force = false;
  /// SGBM's matcher once per keyframe and matcher combination, each speckle variant derived from it (the same
  /// bytes, docs/datasets.md "How generation shares work"); false: every set runs StereoSGBM::compute with its
  /// full parameters, the path before sharing (the oracle of the tests and the benchmark's baseline).
  bool share_matcher = true;
};

/// A filtered point further than this from every true surface is a phantom: a voxel centroid of points on a
/// surface is at most half a 0.1 m voxel's diagonal (0.087 m) away, plus depth noise.
inline constexpr double kOffSurface = 0.2;
/// s_c of the paper: far points are inaccurate by nature (depth error grows with z^2) and only free space.
inline constexpr double kNearRange = 4.0;

struct PointCloudSetSummary {
  std::string folder;              ///< pcs-NNNN (grid id) or pcs-custom
  std::int64_t id = -1;            ///< grid id, -1 for --sgbm
  SgbmParams params;
  std::uint64_t points = 0, scans = 0;
  double target_valid_fraction = 0;  ///< target pixels of the left images with a valid disparity
  double off_surface_fraction = 0;   ///< of the points within kNearRange of their camera, those more than
                                     ///< kOffSurface from every true surface (phantoms)
  ConfusionCounts naive;
  int rank = 0;                    ///< by naive FDR, 1st is best (ties: higher TPR, then lower id)
  double seconds = 0;              ///< SGBM, reprojection, filter and writing (not deterministic: timing.json);
                                   ///< with share_matcher, the matcher's time in equal shares of its group
};

struct DatasetSummary {
  std::string name, scale;
  std::vector<PointCloudSetSummary> sets;  ///< in rank order
  double render_seconds = 0;
  [[nodiscard]] const PointCloudSetSummary& medianRanked() const;  ///< rank (n + 1) / 2
};

/// One data set's keyframes: true poses (images are rendered from these), the poses the clouds are placed with
/// (`config.drift` applied), and the rendered pairs.
struct Keyframes {
  std::vector<CameraPose> truth, mapping;
  std::vector<StereoFrame> frames;
};
/// Keyframes of the orbit for `config.scale.keyframes`; `base_seed` seeds the sensor noise and the pose error.
[[nodiscard]] Keyframes renderKeyframes(const Scene& scene, const StereoCamera& camera, const GenerateConfig& config,
                                        std::uint64_t base_seed);

/// Renders, runs SGBM per set, writes OUT/<name>/pcs-*/ data sets, OUT/<name>/ranking.json (deterministic) and
/// OUT/<name>/timing.json; progress on stderr. Folders are written under temporary names and renamed.
[[nodiscard]] DatasetSummary generateDataset(const DatasetName& name, const GenerateConfig& config,
                                             const PointCloudGrid& grid, const std::filesystem::path& out_root);

/// A preview PNG of occsweep's, proven by its Software chunk.
[[nodiscard]] ReplaceableOutput previewOutput();

/// Writes a PNG of a grey image, a disparity map (colour-coded, invalid black) or both. Temporary name + rename.
void writeGreyPng(const GreyImage& image, const std::filesystem::path& file);
void writeDisparityPng(const std::vector<std::int16_t>& disparity, int width, int height, int num_disparities,
                       const std::filesystem::path& file);

}  // namespace occsweep::stereo
