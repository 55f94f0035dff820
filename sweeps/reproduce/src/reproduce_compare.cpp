// Fig. 5 (Section 4.3-4.4): the best AUC of OctoMap over octomap-opt (180 combinations) and of k-NN over knn-opt
// (4,050) on the 1st, 800th and 1,600th ranked point cloud sets of each data set (first, median, last at smaller
// scales), and the improvement of k-NN in percent.
#include <map>

#include "occsweep/sweeps/compare_statistics.hpp"
#include "occsweep/sweeps/compare.hpp"
#include "occsweep/sweeps/compare_units.hpp"
#include "reproduce_internal.hpp"

namespace occsweep {
using nlohmann::json;

namespace {

json bestJson(const std::optional<BestMap>& b, const ResultsFile& f) {
  if (!b) return nullptr;
  MapResult params_only;
  params_only.params = b->params;
  return {{"auc", finiteNumber(b->auc)}, {"auc_observed", finiteNumber(b->observed)}, {"map_index", b->map_index},
          {"params", toJson(params_only, f.header.parameters).at("params")}};
}

// The highest TPR any map of either grid reaches at any p_t: the ceiling the truth puts on the curves (on the
// Fig. 6 set no combination passes it, not even at p_t = p_min; docs/fidelity.md).
double tprCeiling(const ResultsFile& om, const ResultsFile& knn) {
  double ceiling = NAN;
  for (const ResultsFile* f : {&om, &knn})
    for (const auto& m : f->maps)
      for (const auto& t : m.thresholds)
        if (std::isfinite(t.counts.tpr()) && !(t.counts.tpr() <= ceiling)) ceiling = t.counts.tpr();
  return ceiling;
}

// One truth's side of a row: both best maps, the improvement and the TPR ceiling.
json truthJson(const ResultsFile& om, const ResultsFile& knn) {
  const ComparisonRow row = compareBest({om, knn}).at(0);
  std::uint64_t positives = 0;
  if (!om.maps.empty() && !om.maps.front().thresholds.empty())
    positives = om.maps.front().thresholds.front().counts.tp + om.maps.front().thresholds.front().counts.fn;
  return {{"octomap", bestJson(row.best("octomap"), om)}, {"knn", bestJson(row.best("knn"), knn)},
          {"improvement_percent", finiteNumber(row.improvementPercent("knn", "octomap"))}, {"tpr_ceiling", finiteNumber(tprCeiling(om, knn))},
          {"true_voxels", positives}};
}

// The baselines of docs/methods.md: "does k-NN beat filtering the outliers first, then OctoMap?"
constexpr const char* kBaselineGrids[] = {"sor-octomap-opt", "ror-octomap-opt", "range-octomap-opt"};

// One truth's side of a baseline on one set: its best map, its improvement over the optimal OctoMap, and k-NN's
// improvement over it (percent of the baseline's AUC).
json baselineTruthJson(const ResultsFile& om, const ResultsFile& knn, const ResultsFile& baseline) {
  const ComparisonRow row = compareBest({om, knn, baseline}).at(0);
  return {{"best", bestJson(row.best(baseline.header.method), baseline)},
          {"improvement_over_octomap_percent", finiteNumber(row.improvementPercent(baseline.header.method, "octomap"))},
          {"knn_improvement_percent", finiteNumber(row.improvementPercent("knn", baseline.header.method))}};
}

// Every results file of the comparison, per truth: what the statistics of "Is the gain real?" are computed from.
struct ComparedFiles {
  std::vector<ResultsFile> full, observable;
  void add(const reproduce::BothTruths& b) {
    full.push_back(b.full);
    observable.push_back(b.observable);
  }
};

// Every baseline swept on the set, both truths from the same maps, by method name.
json baselinesJson(const ReproduceConfig& c, const RankedDataset& d, std::size_t rank,
                   const reproduce::BothTruths& om, const reproduce::BothTruths& knn, ComparedFiles& files) {
  json out = json::object();
  for (const char* grid : kBaselineGrids) {
    const reproduce::BothTruths b = reproduce::sweepSetBothTruths(c, d, rank, grid);
    files.add(b);
    out[b.full.header.method] = {{"grid", grid}, {"sweep_seconds", b.full.seconds},
                                 {"full", baselineTruthJson(om.full, knn.full, b.full)},
                                 {"observable", baselineTruthJson(om.observable, knn.observable, b.observable)}};
  }
  return out;
}

const char* rankLabel(std::size_t i, std::size_t count) {
  if (i == 0) return "1st";
  return i + 1 == count ? "last" : "median";
}

}  // namespace

// Is the gain real? Every method against OctoMap over the compared sets (docs/statistics.md), per truth, with the
// scenes as units (from provenance) or, `units` Names, each data set one.
json statisticsJson(const ComparedFiles& files, UnitRule units = UnitRule::Provenance) {
  json out = json::object();
  for (const auto& [truth, f] : {std::pair{"full", &files.full}, {"observable", &files.observable}}) {
    CompareStatisticsOptions options;  // baseline octomap, 95 % BCa, 10,000 resamples, seed 1
    options.units = units;
    out[truth] = toJson(compareStatistics(compareBest(*f), *f, options), options);
  }
  return out;
}

// Each data set's scene as compare's units find it (docs/statistics.md, "Verdicts", rule 1): report.md's trend and
// group findings count scenes, as the verdicts do.
std::map<std::string, std::string> scenesOf(const std::vector<ResultsFile>& files) {
  const std::vector<ComparisonRow> rows = compareBest(files);
  const SampleUnits units = sampleUnits(rows, UnitRule::Provenance);
  std::map<std::string, std::string> scene;
  for (std::size_t i = 0; i < rows.size(); ++i) scene[datasetOf(rows[i].dataset)] = units.of_row[i];
  return scene;
}

json runOptimalComparison(const ReproduceConfig& c, const std::vector<RankedDataset>& all) {
  json rows = json::array();
  ComparedFiles files;
  for (const RankedDataset& d : all) {
    const auto ranks = d.paperRanks();
    for (std::size_t i = 0; i < ranks.size(); ++i) {
      // Both truths from the same maps (docs/results-format.md, "Truth").
      const reproduce::BothTruths om_both = reproduce::sweepSetBothTruths(c, d, ranks[i], "octomap-opt");
      const reproduce::BothTruths knn_both = reproduce::sweepSetBothTruths(c, d, ranks[i], "knn-opt");
      files.add(om_both);
      files.add(knn_both);
      const json full = truthJson(om_both.full, knn_both.full);  // also the row's own columns, the paper's truth
      // name = environment-texture-layout (docs/datasets.md)
      const auto dash1 = d.name.find('-'), dash2 = d.name.rfind('-');
      rows.push_back({{"dataset", d.name}, {"environment", d.name.substr(0, dash1)},
                      {"texture", d.name.substr(dash1 + 1, dash2 - dash1 - 1)}, {"layout", d.name.substr(dash2 + 1)},
                      {"rank_label", rankLabel(i, ranks.size())}, {"rank", ranks[i] + 1},
                      {"sets_ranked", d.folders.size()}, {"point_cloud_set", d.folders[ranks[i]]},
                      {"pointcloud_id", d.ids[ranks[i]]}, {"octomap", full.at("octomap")}, {"knn", full.at("knn")},
                      {"improvement_percent", full.at("improvement_percent")},
                      {"sweep_seconds", {{"octomap", om_both.full.seconds}, {"knn", knn_both.full.seconds}}},
                      {"truths", {{"full", full}, {"observable", truthJson(om_both.observable, knn_both.observable)}}},
                      {"baselines", baselinesJson(c, d, ranks[i], om_both, knn_both, files)}});
    }
  }
  const auto scene = scenesOf(files.full);
  for (json& row : rows) {
    const auto of_row = scene.find(row.at("dataset").get<std::string>());
    row["scene"] = of_row != scene.end() ? json(of_row->second) : row.at("dataset");
  }
  return {{"format", "occsweep-reproduce-comparison"}, {"figure", "Fig. 5"},
          {"grids", {{"octomap", "octomap-opt"}, {"knn", "knn-opt"}}}, {"baseline_grids", kBaselineGrids},
          {"auc", "anchored TPR-FDR trapezoid (docs/definitions.md, Confusion counts and AUC)"}, {"rows", rows},
          {"statistics", statisticsJson(files)}, {"statistics_by_data_set", statisticsJson(files, UnitRule::Names)}};
}

}  // namespace occsweep
