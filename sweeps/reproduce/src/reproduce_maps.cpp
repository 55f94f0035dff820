// Fig. 6 (Section 4.4): the TPR-FDR curves of both methods' best combinations on the map data set's 1st ranked
// set, and both maps at two points of similar FDR, as coloured PLY (TP blue, FP red, FN yellow; TN left out as
// in the paper).
#include <cmath>
#include <fstream>
#include <unistd.h>

#include "occsweep/core/log_odds.hpp"
#include "occsweep/eval/dataset.hpp"
#include "occsweep/eval/confusion.hpp"
#include "occsweep/io/output_file.hpp"

#include "occsweep/sweeps/map_recipe.hpp"
#include "reproduce_internal.hpp"

namespace occsweep {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

struct Point {
  double p_t, fdr, tpr;
};

const MapResult& mapOf(const ResultsFile& f, std::uint64_t map_index) {
  for (const MapResult& m : f.maps)
    if (m.map_index == map_index) return m;
  throw std::runtime_error(f.header.dataset_name + ": best map " + std::to_string(map_index) + " not in results");
}

// The map's (FDR, TPR) at each p_t where both are defined.
std::vector<Point> curveOf(const MapResult& m) {
  std::vector<Point> curve;
  for (const auto& t : m.thresholds)
    if (std::isfinite(t.counts.tpr()) && std::isfinite(t.counts.fdr()))
      curve.push_back({toDouble(t.p_t), t.counts.fdr(), t.counts.tpr()});
  return curve;
}

// Two points of similar FDR (Fig. 6): OctoMap's point of largest TPR - FDR (its best trade-off; the paper does
// not say which it took), then the k-NN point nearest to it in FDR, ties to the higher TPR.
std::pair<std::size_t, std::size_t> similarFdr(const std::vector<Point>& om, const std::vector<Point>& knn) {
  std::size_t a = 0, b = 0;
  for (std::size_t i = 1; i < om.size(); ++i)
    if (om[i].tpr - om[i].fdr > om[a].tpr - om[a].fdr) a = i;
  for (std::size_t j = 1; j < knn.size(); ++j) {
    const double gap = std::abs(knn[j].fdr - om[a].fdr), best = std::abs(knn[b].fdr - om[a].fdr);
    if (gap < best || (gap == best && knn[j].tpr > knn[b].tpr)) b = j;
  }
  return {a, b};
}

// Classifies every region voxel of the map at p_t (as classify(): known and log-odds >= l(p_t) in float) and
// writes the TP, FP and FN voxel centres as an ASCII PLY.
// The third line of every classified map this step writes: what proves a PLY at that name occsweep's.
constexpr const char* kMapComment = "comment occsweep reproduce: TP blue, FP red, FN yellow (paper Fig. 6)";

ReplaceableOutput reproductionMapOutput() {
  return {"reproduction map", [](const fs::path& file) {
            std::ifstream in(file);
            std::string line;
            for (int i = 0; i < 3 && std::getline(in, line); ++i) {
            }
            return line == kMapComment;
          }};
}

ConfusionCounts writeClassifiedPly(const octomap::OcTree& map, const GroundTruth& truth, double p_t,
                                   const fs::path& file) {
  const float threshold = logOdds(p_t);
  ConfusionCounts c;
  std::vector<std::pair<octomap::point3d, int>> voxels;  // 0 TP, 1 FP, 2 FN
  forEachRegionVoxel(map, truth, [&](const octomap::OcTreeKey& key, bool truly, const octomap::OcTreeNode* node) {
    const bool predicted = predictedOccupied(node, threshold);
    if (truly && predicted) ++c.tp, voxels.emplace_back(map.keyToCoord(key), 0);
    else if (predicted) ++c.fp, voxels.emplace_back(map.keyToCoord(key), 1);
    else if (truly) ++c.fn, voxels.emplace_back(map.keyToCoord(key), 2);
    else ++c.tn;
  });
  {
    checkOutputTarget(file, true, reproductionMapOutput());  // over an earlier run's map only, never a user's file
    OutputFile ply(file);
    std::ostream& out = ply.stream();
    out << "ply\nformat ascii 1.0\n" << kMapComment << "\n"
        << "comment resolution " << truth.resolution << "\nelement vertex " << voxels.size()
        << "\nproperty float x\nproperty float y\nproperty float z\n"
        << "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n";
    const int colour[3][3] = {{30, 90, 255}, {230, 30, 30}, {250, 210, 0}};
    for (const auto& [p, kind] : voxels)
      out << p.x() << ' ' << p.y() << ' ' << p.z() << ' ' << colour[kind][0] << ' ' << colour[kind][1] << ' '
          << colour[kind][2] << '\n';
    ply.commit();
  }
  return c;
}

json countsJson(const ConfusionCounts& c) {
  return {{"tp", c.tp}, {"fp", c.fp}, {"fn", c.fn}, {"tn", c.tn}, {"tpr", finiteNumber(c.tpr())}, {"fdr", finiteNumber(c.fdr())}};
}

json curveJson(const std::vector<Point>& curve) {
  json j = json::array();
  for (const auto& p : curve) j.push_back({{"p_t", p.p_t}, {"fdr", p.fdr}, {"tpr", p.tpr}});
  return j;
}

}  // namespace

json runCurvesAndMaps(const ReproduceConfig& c, const std::vector<RankedDataset>& all, const json& comparison) {
  const RankedDataset& d = reproduce::datasetOrFirst(all, c.map_dataset);
  const json* row = nullptr;
  for (const auto& r : comparison.at("rows"))
    if (r.at("dataset") == d.name && r.at("rank") == 1) row = &r;
  if (!row || row->at("octomap").is_null() || row->at("knn").is_null())
    throw std::runtime_error("reproduce: no best maps of " + d.name + "'s 1st set in the comparison");
  const ResultsFile om_file = reproduce::sweepSet(c, d, 0, "octomap-opt");
  const ResultsFile knn_file = reproduce::sweepSet(c, d, 0, "knn-opt");
  const MapResult& om_map = mapOf(om_file, row->at("octomap").at("map_index").get<std::uint64_t>());
  const MapResult& knn_map = mapOf(knn_file, row->at("knn").at("map_index").get<std::uint64_t>());
  const auto om_curve = curveOf(om_map), knn_curve = curveOf(knn_map);
  if (om_curve.empty() || knn_curve.empty()) throw std::runtime_error("reproduce: a best curve has no valid point");
  const auto [a, b] = similarFdr(om_curve, knn_curve);

  // Each map built again as its results file says (method, values, resolution, s_c, variant; map_recipe.hpp),
  // directly (liboctomap, the k-NN mapper), not replayed: its counts must equal the sweep's, which the report checks.
  const Dataset data = readDataset(d.root / d.folders[0]);
  const ScoredMapRecipe om = scoredMapRecipe(om_file.header, om_map, d.name + " octomap-opt");
  const ScoredMapRecipe knn = scoredMapRecipe(knn_file.header, knn_map, d.name + " knn-opt");
  const fs::path dir = c.out / "maps";
  fs::create_directories(dir);
  const double om_p_t = om_curve[a].p_t, knn_p_t = knn_curve[b].p_t;
  const ConfusionCounts om_counts = writeClassifiedPly(
      *om.method->buildMap(data.scans, om.values, om.context),
      makeGroundTruth(data.truth, data.region, om.context.map.resolution), om_p_t, dir / "octomap.ply");
  const ConfusionCounts knn_counts = writeClassifiedPly(
      *knn.method->buildMap(data.scans, knn.values, knn.context),
      makeGroundTruth(data.truth, data.region, knn.context.map.resolution), knn_p_t, dir / "knn.ply");
  const bool agree = std::abs(om_counts.fdr() - om_curve[a].fdr) < 1e-12 &&
                     std::abs(om_counts.tpr() - om_curve[a].tpr) < 1e-12 &&
                     std::abs(knn_counts.fdr() - knn_curve[b].fdr) < 1e-12 &&
                     std::abs(knn_counts.tpr() - knn_curve[b].tpr) < 1e-12;
  return {{"format", "occsweep-reproduce-curves"}, {"figure", "Fig. 6"}, {"dataset", d.name},
          {"point_cloud_set", d.folders[0]}, {"rank", 1},
          {"octomap", {{"params", row->at("octomap").at("params")}, {"auc", row->at("octomap").at("auc")},
                       {"curve", curveJson(om_curve)}, {"chosen_p_t", om_p_t}, {"map", "maps/octomap.ply"},
                       {"map_counts", countsJson(om_counts)}}},
          {"knn", {{"params", row->at("knn").at("params")}, {"auc", row->at("knn").at("auc")},
                   {"curve", curveJson(knn_curve)}, {"chosen_p_t", knn_p_t}, {"map", "maps/knn.ply"},
                   {"map_counts", countsJson(knn_counts)}}},
          {"direct_build_matches_sweep", agree}};
}

}  // namespace occsweep
