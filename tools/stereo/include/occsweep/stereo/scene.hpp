// The scenes of the paper's 20 data sets (docs/definitions.md, The 20 data sets): four boxes in a free
// tetromino on a ground plane, in front of building facades or on an open parking lot, plain or Voronoi-textured.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "occsweep/eval/ground_truth.hpp"

namespace occsweep::stereo {

enum class Environment { Building, Parking };
enum class Texture { Plain, Voronoi };
enum class Layout { I, O, T, L, S };

/// ENV-TEXTURE-LAYOUT, e.g. building-voronoi-L.
struct DatasetName {
  Environment environment = Environment::Building;
  Texture texture = Texture::Voronoi;
  Layout layout = Layout::L;
  [[nodiscard]] std::string str() const;
};

/// Throws std::invalid_argument naming the part that is wrong and the accepted values.
[[nodiscard]] DatasetName parseDatasetName(const std::string& name);
/// The 20 names in canonical order: environment, texture, layout (I O T L S).
[[nodiscard]] std::vector<DatasetName> allDatasetNames();

struct SceneConfig {
  double box_edge = 0.5;              ///< cubes, metres (the paper's boxes are about this size)
  double box_height = 0.5;            ///< --box-height: 0.47 puts the tops off the 0.1 m voxel boundaries
  double offset_x = 0.02;             ///< layout shifted off the 0.1 m voxel grid, so faces cut voxels as real
  double offset_y = 0.03;             ///< ones would (same as the built-in scene)
  double facade_distance = 5.0;       ///< building: walls of a square courtyard this far from the targets' centre
  double facade_height = 8.0;         ///< tall enough to fill the view above the targets
  double region_margin = 1.0;         ///< evaluation region: the boxes' bounds grown by this in x and y
  double region_top_margin = 0.5;     ///< and up to this above the boxes; it starts above the ground layer
  bool far_clutter = false;           ///< --far-clutter: buildings and trees 15-60 m away, clouds (not truth)
};

/// The geometry and appearance of one data set's scene. Voxel ground truth is `boxes` inside `region`.
struct Scene {
  DatasetName name;
  SceneConfig config;
  std::vector<AxisBox> boxes;
  AxisBox region;
  Eigen::Vector3d centre;   ///< centre of the boxes' bounds at half box height: what the camera looks at
  std::uint64_t seed = 0;   ///< texture seed (fixed per name, so left and right images see the same world)
};

/// Cells of a free tetromino on a unit grid, in a fixed orientation.
[[nodiscard]] std::vector<std::array<int, 2>> tetrominoCells(Layout layout);

[[nodiscard]] Scene makeScene(const DatasetName& name, const SceneConfig& config = {});

/// Voxel ground truth of a scene at `resolution`: voxels whose cube overlaps a box, inside the region.
[[nodiscard]] GroundTruth sceneGroundTruth(const Scene& scene, double resolution);

}  // namespace occsweep::stereo
