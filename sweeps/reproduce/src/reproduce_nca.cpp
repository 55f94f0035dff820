// Fig. 4 (Section 3.5, 4.3-4.4): NCA feature weights of the k-NN parameters under TPR and FDR. Each data set
// sweeps its Eq. 16 group of the reduction grid (5,625 of 112,500 combinations) on the point cloud parameters of
// building-voronoi-I's median-ranked set (the paper's "800th ranked ... I layout Voronoi ... buildings").
#include <array>
#include <cmath>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "occsweep/core/splitmix64.hpp"
#include "occsweep/stats/nca.hpp"
#include "occsweep/sweeps/progress.hpp"
#include "reproduce_internal.hpp"

namespace occsweep {
using nlohmann::json;

namespace {

const std::vector<std::string> kFeatures = {"p_max", "p_min", "p_m", "p_m_out", "p_u", "p_l", "p_t", "k"};
constexpr std::uint64_t kGroups = 20;  // N_d of Eq. 16: the grid is split over the paper's 20 data sets

struct Samples {
  std::vector<std::array<double, 8>> x;
  std::vector<double> y;
};

// One sample per combination (map parameters and p_t) whose response is a number (paper Section 4.4).
Samples collect(const ResultsFile& f, bool tpr) {
  Samples s;
  for (const auto& m : f.maps)
    for (const auto& t : m.thresholds) {
      const double y = tpr ? t.counts.tpr() : t.counts.fdr();
      if (!std::isfinite(y)) continue;
      const auto value = [&](const char* name) { return parameterValue(f.header.parameters, m.params, name); };
      s.x.push_back({value("p_max"), value("p_min"), value("p_m"), value("p_m_out"), value("p_u"), value("p_l"),
                     toDouble(t.p_t), value("k")});
      s.y.push_back(y);
    }
  return s;
}

// A seeded subset of at most `limit` samples (SplitMix64 Fisher-Yates: the same on every platform).
void subsample(Samples& s, std::size_t limit, std::uint64_t seed) {
  if (limit == 0 || s.y.size() <= limit) return;
  std::vector<std::size_t> order(s.y.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  SplitMix64 rng(seed);
  for (std::size_t i = order.size(); i > 1; --i) std::swap(order[i - 1], order[rng.below(i)]);
  Samples out;
  for (std::size_t i = 0; i < limit; ++i) out.x.push_back(s.x[order[i]]), out.y.push_back(s.y[order[i]]);
  s = std::move(out);
}

// One NCA fit: a data set's samples under one response (TPR or FDR).
struct NcaJob {
  std::size_t dataset;
  bool tpr;
  Samples samples;
  NcaResult result;
};

// The same point cloud parameters in every data set (Section 3.5); the median set if that id is absent.
std::size_t rankOf(const RankedDataset& d, std::int64_t pcs_id) {
  std::size_t rank = d.paperRanks().size() > 1 ? d.paperRanks()[1] : 0;
  for (std::size_t r = 0; r < d.ids.size(); ++r)
    if (d.ids[r] == pcs_id) rank = r;
  return rank;
}

// Sweeps each data set's Eq. 16 group and adds its two fits to `jobs`; returns what each sweep covered.
json sweepForSamples(const ReproduceConfig& c, const std::vector<RankedDataset>& all, std::int64_t pcs_id,
                     std::vector<NcaJob>& jobs) {
  json sets = json::array();
  for (std::size_t i = 0; i < all.size(); ++i) {
    const RankedDataset& d = all[i];
    const std::size_t rank = rankOf(d, pcs_id);
    SweepSelection sel;
    sel.group = SweepSelection::Group{reproduce::paperIndex(d.name, i), kGroups, c.seed};
    const ResultsFile f = reproduce::sweepSet(c, d, rank, c.reduction_grid, sel);
    sets.push_back({{"dataset", d.name}, {"point_cloud_set", d.folders[rank]}, {"group", sel.group->index},
                    {"maps", f.maps.size()}, {"sweep_seconds", f.seconds}});
    for (bool tpr : {true, false}) {
      Samples s = collect(f, tpr);
      sets.back()[tpr ? "samples_tpr" : "samples_fdr"] = s.y.size();
      subsample(s, c.nca_samples, c.seed * 1000003 + i * 2 + (tpr ? 0 : 1));
      jobs.push_back({i, tpr, std::move(s), {}});
    }
  }
  return sets;
}

void fitJobs(const ReproduceConfig& c, std::vector<NcaJob>& jobs) {
  NcaConfig nc;
  nc.folds = c.nca_folds;
  nc.lambda_factors = c.nca_lambda_factors;
  nc.seed = c.seed;
  Progress progress("NCA weights", jobs.size(), c.quiet, "fits");
  tbb::task_arena arena(c.threads > 0 ? c.threads : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(std::size_t(0), jobs.size(), [&](std::size_t j) {
      NcaJob& job = jobs[j];
      Eigen::MatrixXd x(Eigen::Index(job.samples.y.size()), Eigen::Index(kFeatures.size()));
      Eigen::VectorXd y(x.rows());
      for (Eigen::Index i = 0; i < x.rows(); ++i) {
        for (Eigen::Index r = 0; r < x.cols(); ++r) x(i, r) = job.samples.x[std::size_t(i)][std::size_t(r)];
        y(i) = job.samples.y[std::size_t(i)];
      }
      job.result = ncaFeatureWeights(x, y, nc);
      progress.advance();
    }, tbb::simple_partitioner());
  });
}

json weightsPerDataset(const std::vector<RankedDataset>& all, const std::vector<NcaJob>& jobs) {
  json per_dataset = json::array();
  for (std::size_t i = 0; i < all.size(); ++i) {
    json row = {{"dataset", all[i].name}};
    for (const NcaJob& job : jobs) {
      if (job.dataset != i) continue;
      row[job.tpr ? "tpr" : "fdr"] = {{"normalized", job.result.normalized}, {"weights", job.result.weights},
                                      {"lambda", job.result.lambda}, {"lambdas", job.result.lambdas},
                                      {"cv_loss", job.result.cv_loss}, {"samples", job.result.samples},
                                      {"iterations", job.result.iterations}};
    }
    per_dataset.push_back(row);
  }
  return per_dataset;
}

}  // namespace

json runNcaWeights(const ReproduceConfig& c, const std::vector<RankedDataset>& all) {
  const RankedDataset& ref = reproduce::datasetOrFirst(all, c.fit_dataset);
  const std::size_t ref_rank = ref.paperRanks().size() > 1 ? ref.paperRanks()[1] : 0;
  const std::int64_t pcs_id = ref.ids[ref_rank];
  std::vector<NcaJob> jobs;
  const json sets = sweepForSamples(c, all, pcs_id, jobs);
  fitJobs(c, jobs);
  return {{"format", "occsweep-reproduce-nca"}, {"figure", "Fig. 4"}, {"grid", c.reduction_grid},
          {"groups", kGroups}, {"seed", c.seed}, {"pointcloud_id", pcs_id}, {"reference", ref.name},
          {"features", kFeatures}, {"normalization", "|w_r| / sum_r |w_r| per data set and response"},
          {"sample_limit", c.nca_samples}, {"folds", c.nca_folds}, {"lambda_factors", c.nca_lambda_factors},
          {"sweeps", sets}, {"datasets", weightsPerDataset(all, jobs)}};
}

}  // namespace occsweep
