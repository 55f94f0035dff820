// Fig. 7 (Section 3.6, 4.4): run time of single-threaded map builds against the points processed N and k, fitted
// with Eq. 17 (OctoMap, t = aN + b) and Eq. 18 (k-NN, t = (ak + b)N + c) by least squares.
#include <algorithm>
#include <chrono>
#include <cmath>

#include "occsweep/methods/knn/knn_inverse_sensor_model.hpp"
#include "occsweep/methods/octomap/octomap_baseline.hpp"
#include "occsweep/eval/dataset.hpp"
#include "occsweep/stats/runtime_model.hpp"
#include "occsweep/sweeps/progress.hpp"
#include "reproduce_internal.hpp"

namespace occsweep {
using nlohmann::json;

namespace {

template <class Fn>
double fastest(int repeats, Fn&& fn) {
  double best = INFINITY;
  for (int r = 0; r < std::max(repeats, 1); ++r) {
    const auto start = std::chrono::steady_clock::now();
    fn();
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  return best;
}

json fitJson(const RuntimeFit& f, bool eq18) {
  json j = {{"a", f.a}, {"b", f.b}, {"r_squared", f.r_squared}};
  if (eq18) j["c"] = f.c;
  return j;
}

json samplesJson(const std::vector<RuntimeSample>& s, const std::vector<std::string>& names) {
  json j = json::array();
  for (std::size_t i = 0; i < s.size(); ++i)
    j.push_back({{"points", s[i].points}, {"k", s[i].k}, {"seconds", s[i].seconds}, {"dataset", names[i]}});
  return j;
}

// Section 4.4: the point cloud parameters of the reduction (median-ranked set); data sets spread over the list.
std::vector<std::size_t> pickedDatasets(const ReproduceConfig& c, const std::vector<RankedDataset>& all) {
  std::vector<std::size_t> picked;
  const std::size_t count = std::min<std::size_t>(std::max(c.runtime_datasets, 1), all.size());
  for (std::size_t i = 0; i < count; ++i) picked.push_back(i * all.size() / count);
  return picked;
}

// Timed builds of each method, with the name of the data set of each sample.
struct TimedBuilds {
  std::vector<RuntimeSample> s_om, s_knn;
  std::vector<std::string> n_om, n_knn;
};

// Builds of growing prefixes of a data set's median-ranked set: OctoMap, then k-NN for every k.
void timeBuilds(const ReproduceConfig& c, const RankedDataset& d, int fractions, Progress& progress, TimedBuilds& t) {
  // Mapping parameters do not change the work done per point; the paper's fixed p_max, p_min (Table 1 note b).
  OctoMapParams om;
  om.p_max = 0.98, om.p_min = 0.02;
  KnnParams kp;
  kp.p_max = 0.98, kp.p_min = 0.02;
  const std::size_t rank = d.paperRanks().size() > 1 ? d.paperRanks()[1] : 0;
  const Dataset data = readDataset(d.root / d.folders[rank]);
  // One untimed build first: the first build of a process pays for page faults and cold caches.
  (void)KnnInverseSensorModel(kp).buildMap(data.scans);
  for (int f = 1; f <= fractions; ++f) {
    const std::size_t scans = std::max<std::size_t>(1, data.scans.size() * std::size_t(f) / std::size_t(fractions));
    const PointCloudSet part(data.scans.begin(), data.scans.begin() + std::ptrdiff_t(scans));
    const double n = double(pointCount(part));
    t.s_om.push_back({n, 0, fastest(c.runtime_repeats, [&] { (void)buildOctoMap(part, om); })});
    t.n_om.push_back(d.name);
    progress.advance();
    for (int k : c.runtime_k) {
      KnnParams p = kp;
      p.k = k;
      t.s_knn.push_back({n, double(k), fastest(c.runtime_repeats, [&] { (void)KnnInverseSensorModel(p).buildMap(part); })});
      t.n_knn.push_back(d.name);
      progress.advance();
    }
  }
}

std::vector<RuntimeSample> samplesOf(const std::vector<RuntimeSample>& s, const std::vector<std::string>& names,
                                     const std::string& name) {
  std::vector<RuntimeSample> only;
  for (std::size_t j = 0; j < s.size(); ++j)
    if (names[j] == name) only.push_back(s[j]);
  return only;
}

// Per data set too: the work per point depends on the scene (rays of far points are cut at s_c but still
// traversed), so N alone explains less across data sets than within one.
json fitsPerDataset(const std::vector<RankedDataset>& all, const std::vector<std::size_t>& picked, int fractions,
                    const TimedBuilds& t) {
  json per_dataset = json::array();
  if (fractions < 2) return per_dataset;  // one N: nothing to fit
  for (std::size_t i : picked)
    per_dataset.push_back({{"dataset", all[i].name}, {"octomap", fitJson(fitEq17(samplesOf(t.s_om, t.n_om, all[i].name)), false)},
                           {"knn", fitJson(fitEq18(samplesOf(t.s_knn, t.n_knn, all[i].name)), true)}});
  return per_dataset;
}

// Also fit Eq. 17 per k to show that the slope grows with k (Section 4.5).
json fitsPerK(const ReproduceConfig& c, const std::vector<RuntimeSample>& s_knn) {
  json per_k = json::array();
  for (int k : c.runtime_k) {
    std::vector<RuntimeSample> only;
    for (const auto& s : s_knn)
      if (s.k == k) only.push_back(s);
    per_k.push_back({{"k", k}, {"fit", fitJson(fitEq17(only), false)}});
  }
  return per_k;
}

}  // namespace

json runRuntimeModels(const ReproduceConfig& c, const std::vector<RankedDataset>& all) {
  const std::vector<std::size_t> picked = pickedDatasets(c, all);
  const int fractions = std::max(c.runtime_fractions, 1);
  Progress progress("timed builds", picked.size() * std::size_t(fractions) * (1 + c.runtime_k.size()), c.quiet,
                    "builds");
  TimedBuilds t;
  for (std::size_t i : picked) timeBuilds(c, all[i], fractions, progress, t);
  const RuntimeFit f17 = fitEq17(t.s_om), f18 = fitEq18(t.s_knn);
  return {{"format", "occsweep-reproduce-runtime"}, {"figure", "Fig. 7"}, {"threads", 1},
          {"repeats", c.runtime_repeats}, {"fractions", fractions}, {"per_dataset", fitsPerDataset(all, picked, fractions, t)},
          {"octomap", {{"model", "Eq. 17: t = a N + b"}, {"fit", fitJson(f17, false)}, {"samples", samplesJson(t.s_om, t.n_om)}}},
          {"knn", {{"model", "Eq. 18: t = (a k + b) N + c"}, {"fit", fitJson(f18, true)}, {"per_k", fitsPerK(c, t.s_knn)},
                   {"samples", samplesJson(t.s_knn, t.n_knn)}}},
          {"paper", {{"octomap", {{"a", 2.3371e-5}, {"b", 0.69527}}}, {"knn", {{"a", 7.3592e-7}, {"b", 2.7681e-5}, {"c", 1.5148}}}}}};
}

}  // namespace occsweep
