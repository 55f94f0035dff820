// Fig. 3 (Section 3.2, 4.4): the average distances s_i of every in-range point of one point cloud set fitted by
// the normal, log-logistic, Rayleigh and GEV distributions (maximum likelihood) and a Gaussian KDE.
#include <algorithm>

#include "occsweep/eval/dataset.hpp"
#include "occsweep/methods/knn/knn_set_distances.hpp"
#include "occsweep/stats/distribution_fit.hpp"
#include "occsweep/sweeps/tbb_scan_executor.hpp"
#include "reproduce_internal.hpp"

namespace occsweep {
using nlohmann::json;

json runDistributionFits(const ReproduceConfig& c, const std::vector<RankedDataset>& all) {
  // Section 4.4: "the average distance derived by the 800th point cloud set of I layout Voronoi boxes in front
  // of buildings"; the median-ranked set stands for the 800th of 1,600.
  const RankedDataset& d = reproduce::datasetOrFirst(all, c.fit_dataset);
  const std::size_t rank = d.paperRanks().size() > 1 ? d.paperRanks()[1] : 0;
  const Dataset data = readDataset(d.root / d.folders[rank]);
  const double s_c = MapSettings{}.s_c;  // Section 4.2; the s_i are those of z_in (Section 3.2: "within range s_c")
  const KnnSetDistances distances = computeKnnDistances(data.scans, c.fit_k, s_c, tbbScanExecutor());
  std::vector<double> s;
  for (const auto& scan : distances.scans) s.insert(s.end(), scan.s.begin(), scan.s.end());
  const DistributionReport r = fitDistributions(s, 200);

  json fits = json::array();
  double max_pairwise = 0.0, max_empirical = 0.0;
  for (std::size_t a = 0; a < r.fits.size(); ++a) {
    const DistributionFit& f = r.fits[a];
    json params = json::object();
    for (std::size_t p = 0; p < f.params.size(); ++p) params[f.param_names[p]] = f.params[p];
    json cdf = json::array();
    for (double v : r.cdf[a]) cdf.push_back(finiteNumber(v));
    fits.push_back({{"name", distributionName(f.kind)}, {"params", params}, {"nll", finiteNumber(f.nll)},
                    {"aic", finiteNumber(f.aic)}, {"nll_estimated", f.nll_estimated},
                    {"ks_to_empirical", r.ks_empirical[a]}, {"ks", r.ks[a]}, {"cdf", cdf}});
    for (double v : r.ks[a]) max_pairwise = std::max(max_pairwise, v);
    max_empirical = std::max(max_empirical, r.ks_empirical[a]);
  }
  return {{"format", "occsweep-reproduce-fits"}, {"figure", "Fig. 3"}, {"dataset", d.name},
          {"point_cloud_set", d.folders[rank]}, {"rank", rank + 1}, {"sets_ranked", d.folders.size()},
          {"k", c.fit_k}, {"s_c", s_c}, {"samples", r.samples}, {"dropped", r.dropped},
          {"mu", distances.mu}, {"sigma", distances.sigma}, {"grid", r.grid}, {"empirical_cdf", r.empirical_cdf},
          {"fits", fits}, {"max_pairwise_ks", max_pairwise}, {"max_ks_to_empirical", max_empirical}};
}

}  // namespace occsweep
