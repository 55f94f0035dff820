// OctoMap as a registered method (docs/methods.md, "octomap"): the paper's baseline, built by liboctomap itself.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "octomap_baseline.hpp"
#include "octomap_parameters.hpp"
#include "occsweep/core/log_odds.hpp"
#include "occsweep/core/mapping_method.hpp"

namespace occsweep {

/// OctoMap (Hornung et al. 2013; Eq. 4-5): l(p_h) per hit voxel, l(p_m) per crossed voxel. Built by liboctomap.
class OctoMapMethod : public MappingMethod {
 public:
  std::string name() const override { return "octomap"; }
  std::string displayName() const override { return "OctoMap"; }
  std::string description() const override { return "OctoMap: one l(p_h) per hit voxel, l(p_m) per crossed voxel"; }
  std::string reference() const override { return "Hornung et al., Autonomous Robots 34(3), 2013 (Eq. 4-5)"; }
  std::vector<MethodParameter> parameters() const override { return builtin::octomapParameters(); }
  std::vector<ParameterRelation> relations() const override { return builtin::octomapRelations(); }
  MapRule rule(const MethodValues& v, const RuleContext& c) const override;
  std::unique_ptr<octomap::OcTree> buildMap(const PointCloudSet& set, const MethodValues& v,
                                            const MapContext& c) const override;

 protected:
  /// The OctoMap settings of a map (p_t irrelevant: maps are classified at every p_t afterwards).
  OctoMapParams octomapParams(const MethodValues& v, const MapContext& c) const;
};

namespace detail {

/// The clamping bounds and the in-range miss of an OctoMap-family map (l_out = l_in: OctoMap treats every crossed
/// voxel alike).
[[nodiscard]] MapRule octomapFamilyRule(const MappingMethod& m, const MethodValues& v);

}  // namespace detail

// ---------------------------------------------------------------------------------------------------------

inline MapRule detail::octomapFamilyRule(const MappingMethod& m, const MethodValues& v) {
  MapRule rule;
  rule.l_min = logOdds(parameterValue(m, v, "p_min"));
  rule.l_max = logOdds(parameterValue(m, v, "p_max"));
  rule.update.l_in = rule.update.l_out = logOdds(parameterValue(m, v, "p_m"));
  return rule;
}

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

}  // namespace occsweep
