#include "occsweep/stereo/scene.hpp"

#include <algorithm>
#include <array>
#include <stdexcept>

#include "occsweep/eval/paper_datasets.hpp"

namespace occsweep::stereo {
namespace {

// The enums of scene.hpp index the paper's name lists (paper_datasets.hpp) in their order.
constexpr const auto& kEnvironments = kPaperEnvironments;
constexpr const auto& kTextures = kPaperTextures;
constexpr const auto& kLayouts = kPaperLayouts;

template <std::size_t N>
int indexOf(const std::array<const char*, N>& names, const std::string& s) {
  for (std::size_t i = 0; i < N; ++i)
    if (s == names[i]) return int(i);
  return -1;
}

template <std::size_t N>
std::string joined(const std::array<const char*, N>& names) {
  std::string out;
  for (const char* n : names) out += (out.empty() ? "" : ", ") + std::string(n);
  return out;
}

}  // namespace

std::string DatasetName::str() const {
  return std::string(kEnvironments[int(environment)]) + "-" + kTextures[int(texture)] + "-" + kLayouts[int(layout)];
}

DatasetName parseDatasetName(const std::string& name) {
  const auto a = name.find('-'), b = a == std::string::npos ? a : name.find('-', a + 1);
  if (b == std::string::npos)
    throw std::invalid_argument("data set name '" + name + "': must be ENV-TEXTURE-LAYOUT, e.g. building-voronoi-L");
  const int e = indexOf(kEnvironments, name.substr(0, a));
  const int t = indexOf(kTextures, name.substr(a + 1, b - a - 1));
  const int l = indexOf(kLayouts, name.substr(b + 1));
  if (e < 0) throw std::invalid_argument("data set name '" + name + "': environment must be one of " + joined(kEnvironments));
  if (t < 0) throw std::invalid_argument("data set name '" + name + "': texture must be one of " + joined(kTextures));
  if (l < 0) throw std::invalid_argument("data set name '" + name + "': layout must be one of " + joined(kLayouts));
  return {Environment(e), Texture(t), Layout(l)};
}

std::vector<DatasetName> allDatasetNames() {
  std::vector<DatasetName> all;
  for (int e = 0; e < 2; ++e)
    for (int t = 0; t < 2; ++t)
      for (int l = 0; l < 5; ++l) all.push_back({Environment(e), Texture(t), Layout(l)});
  return all;
}

std::vector<std::array<int, 2>> tetrominoCells(Layout layout) {
  switch (layout) {
    case Layout::I: return {{{0, 0}}, {{1, 0}}, {{2, 0}}, {{3, 0}}};
    case Layout::O: return {{{0, 0}}, {{1, 0}}, {{0, 1}}, {{1, 1}}};
    case Layout::T: return {{{0, 0}}, {{1, 0}}, {{2, 0}}, {{1, 1}}};
    case Layout::L: return {{{0, 0}}, {{1, 0}}, {{2, 0}}, {{2, 1}}};
    case Layout::S: return {{{0, 0}}, {{1, 0}}, {{1, 1}}, {{2, 1}}};
  }
  throw std::logic_error("unknown layout");
}

Scene makeScene(const DatasetName& name, const SceneConfig& c) {
  Scene s;
  s.name = name;
  s.config = c;
  const auto cells = tetrominoCells(name.layout);
  int max_i = 0, max_j = 0;
  for (const auto& [i, j] : cells) max_i = std::max(max_i, i), max_j = std::max(max_j, j);
  // Cells centred on the origin to the nearest whole cell, so every layout sits near (0, 0).
  const int shift_i = (max_i + 1) / 2, shift_j = (max_j + 1) / 2;
  const double e = c.box_edge;
  for (const auto& [i, j] : cells) {
    const double x0 = c.offset_x + (i - shift_i) * e, y0 = c.offset_y + (j - shift_j) * e;
    s.boxes.push_back(AxisBox{{x0, y0, 0.0}, {x0 + e, y0 + e, c.box_height}});
  }
  AxisBox bounds = s.boxes.front();
  for (const auto& b : s.boxes)
    for (int a = 0; a < 3; ++a) bounds.min[a] = std::min(bounds.min[a], b.min[a]), bounds.max[a] = std::max(bounds.max[a], b.max[a]);
  // The camera looks at half the cube edge whatever --box-height says: a height change moves no camera.
  s.centre = {(bounds.min[0] + bounds.max[0]) / 2, (bounds.min[1] + bounds.max[1]) / 2, e / 2};
  // Above the ground layer: voxel centres from 0.15 m up at 0.1 m resolution (the ground voxels [0, 0.1] are out).
  s.region = AxisBox{{bounds.min[0] - c.region_margin, bounds.min[1] - c.region_margin, 0.1},
                     {bounds.max[0] + c.region_margin, bounds.max[1] + c.region_margin, bounds.max[2] + c.region_top_margin}};
  // Texture seed from the environment and texture only: the layout changes where boxes stand, not the world.
  s.seed = 0x5EED0000ull + std::uint64_t(name.environment) * 16 + std::uint64_t(name.texture);
  return s;
}

GroundTruth sceneGroundTruth(const Scene& scene, double resolution) {
  TruthSources sources;
  sources.boxes = scene.boxes;
  return makeGroundTruth(sources, scene.region, resolution);
}

}  // namespace occsweep::stereo
