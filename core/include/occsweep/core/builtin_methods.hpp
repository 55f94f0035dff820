// The methods occsweep ships (docs/methods.md cites each): OctoMap, the k-NN inverse sensor model, the two PCL
// outlier filters before OctoMap, and OctoMap with a hit probability that falls with the stereo depth error.
#pragma once

#include <cmath>
#include <limits>

#include "builtin_parameters.hpp"
#include "knn_inverse_sensor_model.hpp"
#include "log_odds.hpp"
#include "mapping_method.hpp"
#include "octomap_baseline.hpp"
#include "point_filters.hpp"

namespace occsweep {

/// The method every other one is compared with unless a command is told otherwise (compare --baseline): OctoMap,
/// the paper's baseline (docs/statistics.md). OctoMapMethod registers under this name.
inline const std::string kDefaultBaseline = "octomap";

/// OctoMap (Hornung et al. 2013; Eq. 4-5): l(p_h) per hit voxel, l(p_m) per crossed voxel. Built by liboctomap.
class OctoMapMethod : public MappingMethod {
 public:
  std::string name() const override { return kDefaultBaseline; }
  std::string displayName() const override { return "OctoMap"; }
  std::string description() const override { return "OctoMap: one l(p_h) per hit voxel, l(p_m) per crossed voxel"; }
  std::string reference() const override { return "Hornung et al., Autonomous Robots 34(3), 2013 (Eq. 4-5)"; }
  std::vector<MethodParameter> parameters() const override;
  std::vector<ParameterRelation> relations() const override;
  MapRule rule(const MethodValues& v, const RuleContext& c) const override;
  std::unique_ptr<octomap::OcTree> buildMap(const PointCloudSet& set, const MethodValues& v,
                                            const MapContext& c) const override;

 protected:
  /// The OctoMap settings of a map (p_t irrelevant: maps are classified at every p_t afterwards).
  OctoMapParams octomapParams(const MethodValues& v, const MapContext& c) const;
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
  std::vector<MethodParameter> parameters() const override;
  std::vector<ParameterRelation> relations() const override;
  std::vector<std::string> sharedByLanes() const override { return {"k", "p_u", "p_l"}; }
  MapRule rule(const MethodValues& v, const RuleContext& c) const override;
  std::unique_ptr<octomap::OcTree> buildMap(const PointCloudSet& set, const MethodValues& v,
                                            const MapContext& c) const override;
  /// The k-NN mapper's settings of a map.
  KnnParams knnParams(const MethodValues& v, const MapContext& c) const;
};

/// PCL's StatisticalOutlierRemoval on each scan, then OctoMap (docs/methods.md, "sor-octomap").
class SorOctoMapMethod final : public OctoMapMethod {
 public:
  std::string name() const override { return "sor-octomap"; }
  std::string displayName() const override { return "SOR + OctoMap"; }
  std::string description() const override {
    return "PCL StatisticalOutlierRemoval (mean distance to k neighbours > mean + std_mul stddev) then OctoMap";
  }
  std::string reference() const override { return "Rusu et al., Robotics and Autonomous Systems 56(11), 2008; PCL 1.13"; }
  std::vector<MethodParameter> parameters() const override;
  std::vector<std::string> sharedByLanes() const override { return {"k"}; }
  MapRule rule(const MethodValues& v, const RuleContext& c) const override;
  std::unique_ptr<octomap::OcTree> buildMap(const PointCloudSet& set, const MethodValues& v,
                                            const MapContext& c) const override;
};

/// PCL's RadiusOutlierRemoval on each scan, then OctoMap (docs/methods.md, "ror-octomap").
class RorOctoMapMethod final : public OctoMapMethod {
 public:
  std::string name() const override { return "ror-octomap"; }
  std::string displayName() const override { return "ROR + OctoMap"; }
  std::string description() const override {
    return "PCL RadiusOutlierRemoval (fewer than min_neighbors points within radius) then OctoMap";
  }
  std::string reference() const override { return "PCL 1.13, pcl::RadiusOutlierRemoval (Rusu and Cousins, ICRA 2011)"; }
  std::vector<MethodParameter> parameters() const override;
  std::vector<std::string> sharedByLanes() const override { return {"radius"}; }
  MapRule rule(const MethodValues& v, const RuleContext& c) const override;
  std::unique_ptr<octomap::OcTree> buildMap(const PointCloudSet& set, const MethodValues& v,
                                            const MapContext& c) const override;
};

/// OctoMap whose hit probability falls with range as the stereo depth error grows with its square
/// (docs/methods.md, "range-octomap"): p_h(r) = 0.5 + (p_h - 0.5) min(1, (r_0 / r)^2), one update per voxel from
/// its nearest point.
class RangeOctoMapMethod final : public MappingMethod {
 public:
  std::string name() const override { return "range-octomap"; }
  std::string displayName() const override { return "range OctoMap"; }
  std::string description() const override {
    return "OctoMap with p_h falling as (r_0/r)^2 beyond r_0: the stereo depth error grows with the square of depth";
  }
  std::string reference() const override {
    return "Nguyen, Izadi and Lovell, 3DIMPVT 2012; weighting as in Oleynikova et al. (voxblox), IROS 2017";
  }
  std::vector<MethodParameter> parameters() const override;
  std::vector<ParameterRelation> relations() const override;
  std::vector<std::string> sharedByLanes() const override { return {"r_0", "p_h"}; }
  MapRule rule(const MethodValues& v, const RuleContext& c) const override;
};

// ---------------------------------------------------------------------------------------------------------
namespace detail {

// The clamping bounds and the in-range miss of a map (l_out = l_in: OctoMap treats every crossed voxel alike).
inline MapRule octomapFamilyRule(const MappingMethod& m, const MethodValues& v) {
  MapRule rule;
  rule.l_min = logOdds(parameterValue(m, v, "p_min"));
  rule.l_max = logOdds(parameterValue(m, v, "p_max"));
  rule.update.l_in = rule.update.l_out = logOdds(parameterValue(m, v, "p_m"));
  return rule;
}

// Each scan's kept points, then liboctomap on what is left (the user's pipeline: filter, then insertPointCloud).
template <class Filter>
PointCloudSet filteredSet(const PointCloudSet& set, Filter&& keep) {
  PointCloudSet out(set.size());
  for (std::size_t t = 0; t < set.size(); ++t) {
    out[t].origin = set[t].origin;
    for (std::uint32_t i : keep(set[t].points)) out[t].points.push_back(set[t].points[i]);
  }
  return out;
}

}  // namespace detail

// --- octomap ---

inline std::vector<MethodParameter> OctoMapMethod::parameters() const { return builtin::octomapParameters(); }

inline std::vector<ParameterRelation> OctoMapMethod::relations() const { return builtin::octomapRelations(); }

inline MapRule OctoMapMethod::rule(const MethodValues& v, const RuleContext&) const {
  MapRule rule = detail::octomapFamilyRule(*this, v);
  rule.hit.l_hit = logOdds(parameterValue(*this, v, "p_h"));
  return rule;  // OctoMap's update is the Default variant: occupied wins
}

inline OctoMapParams OctoMapMethod::octomapParams(const MethodValues& v, const MapContext& c) const {
  OctoMapParams p;
  p.p_h = parameterValue(*this, v, "p_h");
  p.p_m = parameterValue(*this, v, "p_m");
  p.p_max = parameterValue(*this, v, "p_max");
  p.p_min = parameterValue(*this, v, "p_min");
  p.p_t = p.p_min;
  p.map = c.map;
  return p;
}

inline std::unique_ptr<octomap::OcTree> OctoMapMethod::buildMap(const PointCloudSet& set, const MethodValues& v,
                                                                const MapContext& c) const {
  return buildOctoMap(set, octomapParams(v, c));
}

// --- knn ---

inline std::vector<MethodParameter> KnnMethod::parameters() const { return builtin::knnParameters(); }

inline std::vector<ParameterRelation> KnnMethod::relations() const { return builtin::knnRelations(); }

inline MapRule KnnMethod::rule(const MethodValues& v, const RuleContext& c) const {
  MapRule rule;
  rule.l_min = logOdds(parameterValue(*this, v, "p_min"));
  rule.l_max = logOdds(parameterValue(*this, v, "p_max"));
  rule.update = {logOdds(parameterValue(*this, v, "p_m")), logOdds(parameterValue(*this, v, "p_m_out")), c.map.variant};
  const double p_u = parameterValue(*this, v, "p_u"), p_l = parameterValue(*this, v, "p_l");
  rule.hit.kind = HitRule::Kind::PointSum;
  rule.hit.feature = {PointFeature::KnnCdf, parameterValue(*this, v, "k")};
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
  if (c.knn_distances) return model.buildMap(set, c.knn_distances(k), c.executor);
  return model.buildMap(set, computeKnnDistances(set, k, c.map.s_c, c.executor), c.executor);
}

// --- sor-octomap ---

inline std::vector<MethodParameter> SorOctoMapMethod::parameters() const {
  std::vector<MethodParameter> p = {
      {"k", "k", "neighbours of each point averaged (PCL's mean_k)", 50, 1, 100000, false, false, true, "PCL setMeanK"},
      {"std_mul", "std_mul", "removed beyond mean + std_mul standard deviations (PCL's stddev_mult)", 1.0, 0, 1e6,
       false, false, false, "ours: grid values are not negative"}};
  for (MethodParameter& q : OctoMapMethod::parameters()) p.push_back(q);
  return p;
}

inline MapRule SorOctoMapMethod::rule(const MethodValues& v, const RuleContext& c) const {
  MapRule rule = OctoMapMethod::rule(v, c);
  const double std_mul = parameterValue(*this, v, "std_mul");
  // Kept when !(d > mean + std_mul * stddev) (PCL): the score is -d, so kept when -d >= -threshold. A NaN
  // threshold (one point: stddev divides by zero) removes nothing in PCL: -inf keeps every point here.
  rule.gate = PointGate{{PointFeature::SorScore, parameterValue(*this, v, "k")}, [std_mul](const FeatureScanSummary& s) {
                          const double t = sorThreshold(SorDistances{{}, s.mean, s.stddev}, std_mul);
                          return std::isnan(t) ? -std::numeric_limits<double>::infinity() : -t;
                        }};
  return rule;
}

inline std::unique_ptr<octomap::OcTree> SorOctoMapMethod::buildMap(const PointCloudSet& set, const MethodValues& v,
                                                                   const MapContext& c) const {
  const int k = int(parameterValue(*this, v, "k"));
  const double std_mul = parameterValue(*this, v, "std_mul");
  const auto keep = [&](const std::vector<octomap::point3d>& points) { return statisticalOutlierRemoval(points, k, std_mul); };
  return buildOctoMap(detail::filteredSet(set, keep), octomapParams(v, c));
}

// --- ror-octomap ---

inline std::vector<MethodParameter> RorOctoMapMethod::parameters() const {
  std::vector<MethodParameter> p = {
      {"radius", "r", "search radius in metres (PCL's search_radius)", 0.2, 0, 1e6, true, false, false, "PCL setRadiusSearch"},
      {"min_neighbors", "n_min", "removed with fewer neighbours within the radius (PCL's min_pts_radius)", 2, 0, 100000,
       false, false, true, "PCL setMinNeighborsInRadius"}};
  for (MethodParameter& q : OctoMapMethod::parameters()) p.push_back(q);
  return p;
}

inline MapRule RorOctoMapMethod::rule(const MethodValues& v, const RuleContext& c) const {
  MapRule rule = OctoMapMethod::rule(v, c);
  const double min_neighbors = parameterValue(*this, v, "min_neighbors");
  rule.gate = PointGate{{PointFeature::RorNeighbours, parameterValue(*this, v, "radius")},
                        [min_neighbors](const FeatureScanSummary&) { return min_neighbors; }};
  return rule;
}

inline std::unique_ptr<octomap::OcTree> RorOctoMapMethod::buildMap(const PointCloudSet& set, const MethodValues& v,
                                                                   const MapContext& c) const {
  const double radius = parameterValue(*this, v, "radius");
  const int min_neighbors = int(parameterValue(*this, v, "min_neighbors"));
  const auto keep = [&](const std::vector<octomap::point3d>& points) {
    return radiusOutlierRemoval(points, radius, min_neighbors);
  };
  return buildOctoMap(detail::filteredSet(set, keep), octomapParams(v, c));
}

// --- range-octomap ---

inline std::vector<MethodParameter> RangeOctoMapMethod::parameters() const {
  return {{"r_0", "r_0", "range in metres up to which a hit has the full p_h", 2.0, 0, 1e6, true, false, false,
           "ours: a range"},
          builtin::clampMax(), builtin::clampMin(), builtin::hitProbability(), builtin::missIn()};
}

inline std::vector<ParameterRelation> RangeOctoMapMethod::relations() const { return builtin::octomapRelations(); }

inline MapRule RangeOctoMapMethod::rule(const MethodValues& v, const RuleContext&) const {
  MapRule rule = detail::octomapFamilyRule(*this, v);
  const double p_h = parameterValue(*this, v, "p_h"), r_0 = parameterValue(*this, v, "r_0");
  rule.hit.kind = HitRule::Kind::PointMax;
  rule.hit.feature = {PointFeature::Range, 0.0};
  rule.hit.pointLogOdds = [p_h, r_0](double r) {
    const double weight = r <= r_0 ? 1.0 : (r_0 / r) * (r_0 / r);  // depth error ~ r^2 (Nguyen et al. 2012)
    return logOdds(0.5 + (p_h - 0.5) * weight);
  };
  return rule;
}

}  // namespace occsweep
