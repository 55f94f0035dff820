// A mapping method of your own, in one header (docs/methods.md, "Bring your own method"): OctoMap whose hit
// probability grows with how crowded the voxel's best point is. A point with `n_full` or more neighbours within
// `radius` counts l(p_h); a lonelier one counts l(p_h) scaled by its share of n_full; the voxel takes its best point.
// Nothing here is occsweep's own code: the method only declares parameters, relations and a rule, and both engines
// sweep it (the replay engine from recorded events, the direct engine through the same rule).
#pragma once

#include <algorithm>

#include <occsweep/core/log_odds.hpp>
#include <occsweep/core/mapping_method.hpp>
#include <occsweep/methods/outlier_filters/outlier_filter_methods.hpp>  // RorNeighboursFeature

class DensityOctoMapMethod final : public occsweep::MappingMethod {
 public:
  std::string name() const override { return "density-octomap"; }
  std::string description() const override {
    return "example: OctoMap with l(p_h) scaled by the best point's share of n_full neighbours within radius";
  }
  std::string reference() const override { return "examples/occupancy_method/example_method.hpp"; }

  // In the order grids enumerate them; p_max and p_min are every method's clamping thresholds.
  std::vector<occsweep::MethodParameter> parameters() const override {
    return {{"radius", "r", "neighbour radius, metres", 0.2, 0.0, 10.0, true, false, false, "a radius"},
            {"n_full", "n", "neighbours for the full p_h", 5, 1, 1000, false, false, true, "a count"},
            {"p_max", "p_max", "upper clamping threshold", 0.97, 0.5, 1.0, false, true, false, "Eq. 12"},
            {"p_min", "p_min", "lower clamping threshold", 0.12, 0.0, 0.5, true, true, false, "Eq. 12"},
            {"p_h", "p_h", "hit of a crowded point", 0.7, 0.5, 1.0, false, true, false, "Eq. 12"},
            {"p_m", "p_m", "miss", 0.4, 0.0, 0.5, true, true, false, "Eq. 12"}};
  }
  std::vector<occsweep::ParameterRelation> relations() const override {
    return {{"p_max", "p_h", false, "Eq. 12"}, {"p_m", "p_min", false, "Eq. 12"}};
  }
  // Maps that share these replay together: the hit rule depends on them alone.
  std::vector<std::string> sharedByLanes() const override { return {"radius", "n_full", "p_h"}; }

  occsweep::MapRule rule(const occsweep::MethodValues& v, const occsweep::RuleContext&) const override {
    using occsweep::logOdds;
    occsweep::MapRule rule;
    rule.l_min = logOdds(value(v, "p_min"));
    rule.l_max = logOdds(value(v, "p_max"));
    rule.update.l_in = rule.update.l_out = logOdds(value(v, "p_m"));
    rule.hit.kind = occsweep::HitRule::Kind::PointMax;  // one update per voxel, from its best point
    rule.hit.feature = std::make_shared<occsweep::RorNeighboursFeature>(value(v, "radius"));
    const double l_hit = logOdds(value(v, "p_h")), n_full = value(v, "n_full");
    rule.hit.pointLogOdds = [=](double neighbours) { return float(l_hit * std::min(1.0, neighbours / n_full)); };
    return rule;
  }

 private:
  double value(const occsweep::MethodValues& v, const std::string& name) const {
    return occsweep::parameterValue(*this, v, name);
  }
};
