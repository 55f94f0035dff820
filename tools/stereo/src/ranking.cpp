#include "occsweep/stereo/ranking.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <stdexcept>
#include <unistd.h>

#include "occsweep/eval/provenance.hpp"
#include "occsweep/io/output_file.hpp"
#include "occsweep/stereo/realism.hpp"

namespace occsweep::stereo {
namespace {

nlohmann::json countsJson(const ConfusionCounts& c) {
  return {{"tp", c.tp}, {"fp", c.fp}, {"fn", c.fn}, {"tn", c.tn}, {"tpr", c.tpr()}, {"fdr", c.fdr()}};
}

nlohmann::json setJson(const PointCloudSetSummary& s) {
  return {{"rank", s.rank},     {"folder", s.folder}, {"id", s.id},       {"params", s.params.toJson()},
          {"points", s.points}, {"scans", s.scans},   {"target_valid_fraction", s.target_valid_fraction},
          {"off_surface_fraction", s.off_surface_fraction},
          {"naive", countsJson(s.naive)}};
}

// The scene's geometry (environment, layout, boxes, courtyard, clutter, region), not its appearance (texture,
// lighting, noise, seed, SGBM settings) or trajectory (camera, orbit, keyframes, pose error): every recording of one
// world is one unit of compare's tests (docs/datasets.md, "Decisions"; docs/statistics.md, "Verdicts").
std::string sceneHash(const DatasetName& name, const GenerateConfig& c) {
  DatasetName geometry = name;
  geometry.texture = Texture::Plain;
  const SceneConfig& g = c.scene;
  const nlohmann::json scene = {
      {"generator", "occsweep dataset generate"}, {"geometry", geometry.str()},
      {"boxes", {g.box_edge, g.box_height, g.offset_x, g.offset_y}}, {"courtyard", {g.facade_distance, g.facade_height}},
      {"region", {g.region_margin, g.region_top_margin}}, {"far_clutter", g.far_clutter}};
  return contentHash(scene.dump());
}

}  // namespace

ScaleConfig scaleConfig(const std::string& name) {
  if (name == "ci") return {"ci", 320, 180, 24, 32, 3};
  if (name == "small") return {"small", 640, 360, 48, 64, 9};
  if (name == "paper") return {"paper", 1280, 720, 144, 128, 0};
  throw std::invalid_argument("scale '" + name + "': must be ci, small or paper");
}

const PointCloudSetSummary& DatasetSummary::medianRanked() const {
  if (sets.empty()) throw std::logic_error("no point cloud set");
  return sets[(sets.size() + 1) / 2 - 1];
}

nlohmann::json sourceJson(const DatasetName& name, const GenerateConfig& c, const StereoCamera& cam,
                          const PointCloudGrid& grid, std::int64_t id, const SgbmParams& params) {
  nlohmann::json j;
  j["generator"] = "occsweep dataset generate";
  j["dataset"] = name.str();
  j["scale"] = c.scale.name;
  j["seed"] = c.seed;
  j["camera"] = {{"width", cam.width}, {"height", cam.height}, {"fx", cam.fx}, {"cx", cam.cx}, {"cy", cam.cy},
                 {"baseline", cam.baseline}};
  j["orbit"] = {{"keyframes", c.scale.keyframes}, {"radius", c.orbit.radius}, {"height", c.orbit.height},
                {"second_orbit_rise", c.orbit.second_orbit_rise}};
  j["pose_drift"] = {{"metres_per_keyframe", c.drift.metres_per_keyframe},
                     {"yaw_deg_per_keyframe", c.drift.yaw_deg_per_keyframe},
                     {"note", "scan origins and points use the drifted poses; images use the true ones"}};
  j["render"] = {{"supersample", c.render.supersample}, {"read_noise", c.render.read_noise},
                 {"shot_noise", c.render.shot_noise}, {"noise", c.render.noise}};
  j["sgbm"] = sgbmSettingsJson(params, c.scale.num_disparities);
  j["pointcloud_id"] = id;
  j["pointcloud_grid"] = {{"name", grid.name}, {"file_hash", grid.file_hash}, {"size", grid.size()}};
  j["voxel_filter_leaf"] = c.leaf;
  j["max_depth"] = c.max_depth;
  if (const auto options = realismOptionsJson(c); !options.empty()) j["options"] = options;
  j["provenance"] = {{"scene", sceneHash(name, c)}};
  return j;
}

void rankSets(std::vector<PointCloudSetSummary>& sets) {
  std::sort(sets.begin(), sets.end(), [](const PointCloudSetSummary& a, const PointCloudSetSummary& b) {
    const double fa = a.naive.fdr(), fb = b.naive.fdr();
    if (std::isnan(fa) != std::isnan(fb)) return std::isnan(fb);
    if (!std::isnan(fa) && fa != fb) return fa < fb;
    const double ta = a.naive.tpr(), tb = b.naive.tpr();
    if (!std::isnan(ta) && !std::isnan(tb) && ta != tb) return ta > tb;
    return a.id < b.id;
  });
  for (std::size_t i = 0; i < sets.size(); ++i) sets[i].rank = int(i + 1);
}

ReplaceableOutput rankingOutput() { return jsonOutput("point cloud ranking", "occsweep-pointcloud-ranking"); }
ReplaceableOutput timingOutput() { return jsonOutput("generation timing", "occsweep-pointcloud-timing"); }

void writeRanking(const DatasetSummary& s, const GenerateConfig& c, const PointCloudGrid& grid,
                  const std::filesystem::path& dir) {
  nlohmann::json ranking = {{"format", "occsweep-pointcloud-ranking"}, {"version", 1}, {"dataset", s.name},
                            {"scale", s.scale}, {"seed", c.seed},
                            {"pointcloud_grid", {{"name", grid.name}, {"file_hash", grid.file_hash}}},
                            {"ranked_by", "naive FDR ascending (NaN last), then TPR descending, then id"},
                            {"sets", nlohmann::json::array()}};
  nlohmann::json timing = {{"format", "occsweep-pointcloud-timing"}, {"dataset", s.name}, {"scale", s.scale},
                           {"render_seconds", s.render_seconds},
                           {"keyframes", c.scale.keyframes}, {"sets", nlohmann::json::array()}};
  if (const auto options = realismOptionsJson(c); !options.empty()) ranking["options"] = options;
  for (const auto& set : s.sets) {
    ranking["sets"].push_back(setJson(set));
    timing["sets"].push_back({{"folder", set.folder}, {"seconds", set.seconds}});
  }
  // Rewritten in a data-set folder a run resumes in: only over occsweep's own (docs/io.md, "Ownership").
  checkOutputTarget(dir / "ranking.json", true, rankingOutput());
  checkOutputTarget(dir / "timing.json", true, timingOutput());
  writeJsonAtomically(ranking, dir / "ranking.json");
  writeJsonAtomically(timing, dir / "timing.json");
}

nlohmann::json summaryRow(const DatasetSummary& s) {
  const auto& median = s.medianRanked();
  double set_seconds = 0;
  for (const auto& set : s.sets) set_seconds += set.seconds;
  return {{"dataset", s.name},
          {"scale", s.scale},
          {"sets", s.sets.size()},
          {"median", setJson(median)},
          {"best", setJson(s.sets.front())},
          {"worst", setJson(s.sets.back())},
          {"render_seconds", s.render_seconds},
          {"sgbm_seconds_per_set", set_seconds / double(s.sets.size())}};
}

}  // namespace occsweep::stereo
