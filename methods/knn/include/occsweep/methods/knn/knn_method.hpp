// The k-NN inverse sensor model as a registered method (docs/methods.md, "knn"): its parameters, its feature F(s_j)
// and its update rule (Algorithm 1), built directly by its own mapper.
#pragma once

#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "knn_inverse_sensor_model.hpp"
#include "knn_parameters.hpp"
#include "occsweep/core/mapping_method.hpp"

namespace occsweep {

/// F(s_j) of Eq. 8 at every in-range point (NaN beyond s_c): the normal CDF of the point's mean distance to its k
/// nearest neighbours in z_in, with mu, sigma of the set (batch) or of the scans so far (online).
class KnnCdfFeature final : public PointFeature {
 public:
  KnnCdfFeature(int k, const MapSettings& map) : k_(k), s_c_(map.s_c), stats_(map.stats) {}
  FeatureIdentity identity() const override { return {"knn-cdf", {double(k_), s_c_}, toText(stats_)}; }
  SetFeature compute(const PointCloudSet& set, const ScanExecutor& executor) const override;
  /// At the hits only: the distances of every point are needed for mu and sigma, but the normal CDF, the costly
  /// part, only where a hit is (most points of a scan are no hit inside the evaluated region).
  std::vector<double> valuesAtHits(const PointCloudSet& set, const HitPoints& hits,
                                   const ScanExecutor& executor) const override;

 private:
  /// F(s_j) of point j of z_in of scan t.
  double cdf(const KnnSetDistances& d, std::size_t t, std::size_t j) const;

  int k_;
  double s_c_;
  StatsMode stats_;
};

/// The k-NN inverse sensor model (Miao, Hunter and Georgilas 2022; Eq. 6-10, Algorithm 1).
class KnnMethod final : public MappingMethod {
 public:
  std::string name() const override { return "knn"; }
  std::string displayName() const override { return "k-NN"; }
  std::string description() const override {
    return "k-NN inverse sensor model: a hit's probability falls with its mean distance to its k nearest neighbours";
  }
  std::string reference() const override { return "Miao, Hunter and Georgilas, Sensors 22, 2022 (Algorithm 1)"; }
  std::vector<MethodParameter> parameters() const override { return builtin::knnParameters(); }
  std::vector<ParameterRelation> relations() const override { return builtin::knnRelations(); }
  std::vector<std::string> sharedByLanes() const override { return {"k", "p_u", "p_l"}; }
  MapRule rule(const MethodValues& v, const RuleContext& c) const override;
  /// The k-NN mapper, with the set's distances for k and s_c shared by the maps of a sweep (MapContext::shared).
  std::unique_ptr<octomap::OcTree> buildMap(const PointCloudSet& set, const MethodValues& v,
                                            const MapContext& c) const override;
  /// The k-NN mapper's settings of a map.
  KnnParams knnParams(const MethodValues& v, const MapContext& c) const;
};

// ---------------------------------------------------------------------------------------------------------

inline double KnnCdfFeature::cdf(const KnnSetDistances& d, std::size_t t, std::size_t j) const {
  const KnnScanDistances& scan = d.scans[t];
  const bool online = stats_ == StatsMode::Online;
  return normalCdf(scan.s[j], online ? scan.online_mu : d.mu, online ? scan.online_sigma : d.sigma);
}

inline SetFeature KnnCdfFeature::compute(const PointCloudSet& set, const ScanExecutor& executor) const {
  const KnnSetDistances d = computeKnnDistances(set, k_, s_c_, executor);
  SetFeature out;
  out.values.resize(set.size());
  out.summaries.assign(set.size(), {});
  for (std::size_t t = 0; t < set.size(); ++t) {
    out.values[t].assign(set[t].points.size(), std::numeric_limits<double>::quiet_NaN());
    for (std::size_t j = 0; j < d.scans[t].inner.size(); ++j) out.values[t][d.scans[t].inner[j]] = cdf(d, t, j);
  }
  return out;
}

inline std::vector<double> KnnCdfFeature::valuesAtHits(const PointCloudSet& set, const HitPoints& hits,
                                                       const ScanExecutor& executor) const {
  if (hits.s_c != s_c_) throw std::invalid_argument("KnnCdfFeature: hits recorded at another s_c");
  const KnnSetDistances d = computeKnnDistances(set, k_, s_c_, executor);
  std::vector<double> out(hits.scan.size());
  for (std::size_t h = 0; h < out.size(); ++h) out[h] = cdf(d, hits.scan[h], hits.inner[h]);  // inner: j in z_in
  return out;
}

inline MapRule KnnMethod::rule(const MethodValues& v, const RuleContext& c) const {
  MapRule rule;
  rule.l_min = logOdds(parameterValue(*this, v, "p_min"));
  rule.l_max = logOdds(parameterValue(*this, v, "p_max"));
  rule.update = {logOdds(parameterValue(*this, v, "p_m")), logOdds(parameterValue(*this, v, "p_m_out")), c.map.variant};
  const double p_u = parameterValue(*this, v, "p_u"), p_l = parameterValue(*this, v, "p_l");
  rule.hit.kind = HitRule::Kind::PointSum;
  rule.hit.feature = std::make_shared<KnnCdfFeature>(int(parameterValue(*this, v, "k")), c.map);
  rule.hit.pointLogOdds = [p_u, p_l](double cdf) { return logOdds(p_u - cdf * (p_u - p_l)); };  // Eq. 6
  return rule;
}

inline KnnParams KnnMethod::knnParams(const MethodValues& v, const MapContext& c) const {
  KnnParams p;
  p.p_u = parameterValue(*this, v, "p_u");
  p.p_l = parameterValue(*this, v, "p_l");
  p.p_m = parameterValue(*this, v, "p_m");
  p.p_m_out = parameterValue(*this, v, "p_m_out");
  p.p_max = parameterValue(*this, v, "p_max");
  p.p_min = parameterValue(*this, v, "p_min");
  p.p_t = p.p_min;
  p.k = int(parameterValue(*this, v, "k"));
  p.map = c.map;
  return p;
}

inline std::unique_ptr<octomap::OcTree> KnnMethod::buildMap(const PointCloudSet& set, const MethodValues& v,
                                                            const MapContext& c) const {
  const KnnInverseSensorModel model(knnParams(v, c));
  const int k = model.params().k;
  if (!c.shared) return model.buildMap(set, computeKnnDistances(set, k, c.map.s_c, c.executor), c.executor);
  const FeatureIdentity distances{"knn-distances", {double(k), c.map.s_c}, ""};
  const auto compute = [&] { return computeKnnDistances(set, k, c.map.s_c); };
  return model.buildMap(set, c.shared->get<KnnSetDistances>(distances, compute), c.executor);
}

}  // namespace occsweep
