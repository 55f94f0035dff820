// The per-point features methods ask for (mapping_method.hpp, PointFeature), computed for every point of every
// scan. The replay engine and the direct mappers read them from here, so both see the same numbers.
#pragma once

#include <cmath>
#include <limits>
#include <vector>

#include "knn_set_distances.hpp"
#include "mapping_method.hpp"
#include "normal_cdf.hpp"
#include "point_filters.hpp"

namespace occsweep {

/// One feature of every point of a point cloud set.
struct SetFeature {
  FeatureRequest request;
  std::vector<std::vector<double>> values;       ///< per scan, per point (NaN where undefined: KnnCdf beyond s_c)
  std::vector<FeatureScanSummary> summaries;     ///< per scan
};

/// The feature of one scan, for the features that depend on that scan alone (every feature but KnnCdf).
void scanFeature(const Scan& scan, const FeatureRequest& request, std::vector<double>& values,
                 FeatureScanSummary& summary);

/// KnnCdf from the set's k-NN distances: F(s_j) with the set's mu, sigma (batch) or the scan's running ones
/// (online), exactly as the k-NN mapper computes it (pointProbability in normal_cdf.hpp).
void knnCdfFeature(const PointCloudSet& set, const KnnSetDistances& distances, StatsMode stats, SetFeature& out);

/// The feature of every scan; scans in any order through `forEachScan(count, body)` (serial by default; the
/// engines pass a parallel loop). KnnCdf needs the set's distances for its k and s_c (computeKnnDistances).
template <class ForEachScan>
[[nodiscard]] SetFeature setFeature(const PointCloudSet& set, const FeatureRequest& request, double s_c,
                                    StatsMode stats, ForEachScan&& forEachScan);
[[nodiscard]] SetFeature setFeature(const PointCloudSet& set, const FeatureRequest& request, double s_c,
                                    StatsMode stats);

// ---------------------------------------------------------------------------------------------------------

inline void scanFeature(const Scan& scan, const FeatureRequest& request, std::vector<double>& values,
                        FeatureScanSummary& summary) {
  const std::size_t n = scan.points.size();
  values.assign(n, std::numeric_limits<double>::quiet_NaN());
  switch (request.feature) {
    case PointFeature::Range:
      for (std::size_t i = 0; i < n; ++i) values[i] = rangeFromOrigin(scan.points[i], scan.origin);
      return;
    case PointFeature::SorScore: {
      const SorDistances d = sorDistances(scan.points, int(request.argument));
      for (std::size_t i = 0; i < n; ++i) values[i] = -double(d.mean_distance[i]);  // higher: more likely kept
      summary = {d.threshold_mean, d.threshold_stddev};
      return;
    }
    case PointFeature::RorNeighbours: {
      const std::vector<std::uint32_t> counts = rorNeighbourCounts(scan.points, request.argument);
      for (std::size_t i = 0; i < n; ++i) values[i] = double(counts[i]);
      return;
    }
    case PointFeature::KnnCdf:
      throw std::invalid_argument("scanFeature: KnnCdf needs the whole set's statistics (knnCdfFeature)");
  }
}

inline void knnCdfFeature(const PointCloudSet& set, const KnnSetDistances& d, StatsMode stats, SetFeature& out) {
  out.values.resize(set.size());
  out.summaries.assign(set.size(), {});
  for (std::size_t t = 0; t < set.size(); ++t) {
    const KnnScanDistances& scan = d.scans[t];
    const bool online = stats == StatsMode::Online;
    const double mu = online ? scan.online_mu : d.mu, sigma = online ? scan.online_sigma : d.sigma;
    out.values[t].assign(set[t].points.size(), std::numeric_limits<double>::quiet_NaN());
    for (std::size_t j = 0; j < scan.inner.size(); ++j) out.values[t][scan.inner[j]] = normalCdf(scan.s[j], mu, sigma);
  }
}

template <class ForEachScan>
SetFeature setFeature(const PointCloudSet& set, const FeatureRequest& request, double s_c, StatsMode stats,
                      ForEachScan&& forEachScan) {
  SetFeature out;
  out.request = request;
  if (request.feature == PointFeature::KnnCdf) {
    KnnSetDistances d;
    d.k = int(request.argument);
    d.s_c = s_c;
    d.scans.resize(set.size());
    forEachScan(set.size(), [&](std::size_t t) { d.scans[t] = scanKnnDistances(set[t], d.k, s_c); });
    accumulateStatistics(d);  // in scan order: identical to computeKnnDistances
    knnCdfFeature(set, d, stats, out);
    return out;
  }
  out.values.resize(set.size());
  out.summaries.assign(set.size(), {});
  forEachScan(set.size(), [&](std::size_t t) { scanFeature(set[t], request, out.values[t], out.summaries[t]); });
  return out;
}

inline SetFeature setFeature(const PointCloudSet& set, const FeatureRequest& request, double s_c, StatsMode stats) {
  return setFeature(set, request, s_c, stats, [](std::size_t count, auto&& body) {
    for (std::size_t t = 0; t < count; ++t) body(t);
  });
}

}  // namespace occsweep
