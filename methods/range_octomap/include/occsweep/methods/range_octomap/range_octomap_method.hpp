// OctoMap with a hit probability that falls with range as a registered method (docs/methods.md, "range-octomap"):
// its feature (each point's range) and its rule, built directly through the rule (buildMapByRule).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "occsweep/methods/octomap/octomap_method.hpp"

namespace occsweep {

/// |p_j - x_t| as OctoMap's computeUpdate measures it (float components).
class RangeFeature final : public ScanFeature {
 public:
  FeatureIdentity identity() const override { return {"range", {}, ""}; }
  void computeScan(const Scan& scan, std::vector<double>& values, FeatureScanSummary&) const override {
    for (std::size_t i = 0; i < values.size(); ++i) values[i] = rangeFromOrigin(scan.points[i], scan.origin);
  }
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
  std::vector<MethodParameter> parameters() const override {
    return {{"r_0", "r_0", "range in metres up to which a hit has the full p_h", 2.0, 0, 1e6, true, false, false,
             "ours: a range"},
            builtin::clampMax(), builtin::clampMin(), builtin::hitProbability(), builtin::missIn()};
  }
  std::vector<ParameterRelation> relations() const override { return builtin::octomapRelations(); }
  std::vector<std::string> sharedByLanes() const override { return {"r_0", "p_h"}; }
  MapRule rule(const MethodValues& v, const RuleContext&) const override {
    MapRule rule = detail::octomapFamilyRule(*this, v);
    const double p_h = parameterValue(*this, v, "p_h"), r_0 = parameterValue(*this, v, "r_0");
    rule.hit.kind = HitRule::Kind::PointMax;
    rule.hit.feature = std::make_shared<RangeFeature>();
    rule.hit.pointLogOdds = [p_h, r_0](double r) {
      const double weight = r <= r_0 ? 1.0 : (r_0 / r) * (r_0 / r);  // depth error ~ r^2 (Nguyen et al. 2012)
      return logOdds(0.5 + (p_h - 0.5) * weight);
    };
    return rule;
  }
};

}  // namespace occsweep
