// Real stereo with the voxel filter as a swept choice (docs/fidelity.md, "Real stereo with truth"): a real pair's
// point cloud sets without the filter (one point per valid disparity), filtered at half the map resolution and at
// the resolution, swept with octomap-opt and knn-opt at each resolution under full and observable truth. With the
// filter at the map resolution one point is left per voxel and scan, so Eq. 7's per-voxel sum over points has one
// term, as OctoMap's update; below it, the ablation (the best knn-opt map with p_u = p_l, i.e. every point
// weighted alike) shows how much of k-NN's gain that sum alone gives.
#include <cstdio>

#include "occsweep/eval/truth_coverage.hpp"
#include "occsweep/sweeps/compare_statistics.hpp"
#include "occsweep/sweeps/compare.hpp"
#include "reproduce_internal.hpp"

namespace occsweep {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr const char* kOctoMapGrid = "octomap-opt";
constexpr const char* kKnnGrid = "knn-opt";

json bestJson(const std::optional<BestMap>& b, const ResultsFile& f) {
  if (!b) return nullptr;
  MapResult params_only;
  params_only.params = b->params;
  return {{"auc", finiteNumber(b->auc)}, {"map_index", b->map_index},
          {"params", toJson(params_only, f.header.parameters).at("params")}};
}

// The k-NN results restricted to the maps with p_u = p_l: Eq. 7 with every point's hit probability the same, so
// what is left of k-NN against OctoMap is the per-voxel sum over a scan's points.
ResultsFile equalHitProbabilities(const ResultsFile& knn) {
  ResultsFile out = knn;
  out.maps.clear();
  const std::size_t p_u = knn.header.parameters.index("p_u"), p_l = knn.header.parameters.index("p_l");
  for (const MapResult& m : knn.maps)
    if (m.params.values.at(p_u) == m.params.values.at(p_l)) out.maps.push_back(m);
  return out;
}

// TP + FN of any map at any threshold: the truth voxels counted (runSweep's files do not set truth_voxels).
std::uint64_t trueVoxels(const ResultsFile& f) {
  if (f.maps.empty() || f.maps.front().thresholds.empty()) return 0;
  const auto& counts = f.maps.front().thresholds.front().counts;
  return counts.tp + counts.fn;
}

// One set under one truth: both best maps, the ablation's, and the improvements over OctoMap.
json truthJson(const ResultsFile& om, const ResultsFile& knn) {
  const ResultsFile ablation = equalHitProbabilities(knn);
  const ComparisonRow row = compareBest({om, knn}).at(0), equal = compareBest({om, ablation}).at(0);
  return {{"octomap", bestJson(row.best("octomap"), om)}, {"knn", bestJson(row.best("knn"), knn)},
          {"knn_equal_hit", bestJson(equal.best("knn"), ablation)}, {"knn_equal_hit_maps", ablation.maps.size()},
          {"knn_improvement_percent", finiteNumber(row.improvementPercent("knn", "octomap"))},
          {"knn_equal_hit_improvement_percent", finiteNumber(equal.improvementPercent("knn", "octomap"))},
          {"true_voxels", trueVoxels(om)}};
}

// What the scans observe of the full truth and how far their points lie from it, as the sweep measured and recorded
// it, with `sweep`'s warning ("" when none; docs/import.md, "Truth coverage and alignment"): Aloe's one view sees
// about a third of its truth, so full truth measures coverage as much as mapping. Null when the file records none.
json coverageJson(const ResultsFile& full) {
  const std::optional<TruthCoverage>& c = full.header.coverage;
  if (!c) return nullptr;
  return {{"observable_share", finiteNumber(c->observableShare())},
          {"median_point_distance_m", finiteNumber(c->median_point_distance)},
          {"warning", coverageWarning(*c, TruthMode::Full)}};
}

// compareStatistics' verdict for k-NN against OctoMap over the sets of one configuration, per truth: over scenes
// (one here: docs/statistics.md, "Verdicts"), with the per-set interval as description.
json statisticsJson(const std::vector<ResultsFile>& full, const std::vector<ResultsFile>& observable) {
  json out = json::object();
  for (const auto& [truth, files] : {std::pair{"full", &full}, {"observable", &observable}}) {
    const CompareStatisticsOptions options;  // baseline octomap, 95 % BCa, 10,000 resamples, seed 1
    const auto statistics = compareStatistics(compareBest(*files), *files, options);
    for (const MethodStatistics& s : statistics) {
      if (s.method != "knn") continue;
      const auto& per_set = s.improvement_percent;
      out[truth] = {{"sets", s.sets}, {"datasets", s.datasets}, {"better", s.better}, {"worse", s.worse},
                    {"ties", s.ties}, {"verdict", s.optima.verdict.text}, {"basis", s.optima.verdict.basis},
                    {"cross_validated_verdict", s.cross_validated.verdict.text},
                    {"improvement_percent_over_sets",
                     per_set ? json{{"mean", per_set->estimate}, {"lower", per_set->lower}, {"upper", per_set->upper}}
                             : json(nullptr)}};
    }
  }
  return out;
}

// The filter as the data sets record it: false, or its leaf in metres.
json voxelFilterJson(double filter_leaf) { return filter_leaf > 0 ? json(filter_leaf) : json(false); }

// One resolution and filter: the pair's sets, both grids swept on each under both truths.
json configurationJson(const ReproduceConfig& c, double resolution, double filter_leaf, const RealStereoSets& sets,
                       const std::string& name) {
  RankedDataset d{name, c.out / "data" / name, sets.folders, sets.ids};
  json rows = json::array();
  std::vector<ResultsFile> full, observable;
  for (std::size_t i = 0; i < sets.folders.size(); ++i) {
    const auto om = reproduce::sweepSetBothTruths(c, d, i, kOctoMapGrid, resolution);
    const auto knn = reproduce::sweepSetBothTruths(c, d, i, kKnnGrid, resolution);
    full.insert(full.end(), {om.full, knn.full});
    observable.insert(observable.end(), {om.observable, knn.observable});
    rows.push_back({{"point_cloud_set", sets.folders[i]}, {"pointcloud_id", sets.ids[i]},
                    {"points", i < sets.points.size() ? json(sets.points[i]) : json(nullptr)},
                    {"sweep_seconds", {{"octomap", om.full.seconds}, {"knn", knn.full.seconds}}},
                    {"coverage", coverageJson(om.full)},
                    {"truths", {{"full", truthJson(om.full, knn.full)},
                                {"observable", truthJson(om.observable, knn.observable)}}}});
  }
  return {{"resolution", resolution}, {"folder", (fs::path("data") / name).string()},
          {"voxel_filter", voxelFilterJson(filter_leaf)}, {"sets", rows}, {"statistics", statisticsJson(full, observable)}};
}

}  // namespace

json runRealStereo(const ReproduceConfig& c) {
  json out = {{"format", "occsweep-reproduce-real-stereo"}, {"grids", {{"octomap", kOctoMapGrid}, {"knn", kKnnGrid}}},
              {"ablation", "knn_equal_hit: the best knn-opt map with p_u = p_l (Eq. 7's per-voxel sum, no k-NN "
                           "weighting)"},
              {"auc", "anchored TPR-FDR trapezoid (docs/definitions.md, Confusion counts and AUC)"},
              {"configurations", json::array()}};
  if (!c.write_real_stereo) {
    out["not_run"] = "this program hands in no real stereo pair (a build without the stereo tools)";
    return out;
  }
  for (const double resolution : c.real_stereo_resolutions)
    for (const double fraction : c.real_stereo_filters) {
      const double filter_leaf = fraction * resolution;
      char configuration[48];
      if (filter_leaf > 0) std::snprintf(configuration, sizeof configuration, "%.3g-filter-%.3g", resolution, filter_leaf);
      else std::snprintf(configuration, sizeof configuration, "%.3g-unfiltered", resolution);
      const std::string name = std::string("real-stereo/") + configuration;
      if (!c.quiet) std::fprintf(stderr, "reproduce: real-stereo: sets %s\n", configuration);
      const RealStereoSets sets = c.write_real_stereo(c.out / "data" / name, resolution, filter_leaf);
      if (!sets.not_available.empty() || sets.folders.empty()) {
        out["not_run"] = sets.not_available.empty() ? "the pair gave no point cloud set" : sets.not_available;
        return out;
      }
      out["pair"] = sets.pair;
      out["configurations"].push_back(configurationJson(c, resolution, filter_leaf, sets, name));
    }
  return out;
}

}  // namespace occsweep
