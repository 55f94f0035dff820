// A mapping method as data the engines can sweep (docs/methods.md): its parameters and the relations among them
// (as Eq. 12 states them for OctoMap and k-NN), what it needs per point, and how one scan's events change a voxel.
// A method written this way is replayed from recorded events and built directly through the same rule, with no
// code of its own in either engine.
#pragma once

#include <compare>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <octomap/OcTree.h>

#include "map_settings.hpp"
#include "method_parameter.hpp"
#include "point_cloud_set.hpp"
#include "point_feature.hpp"
#include "scan_executor.hpp"
#include "voxel_update_rule.hpp"

namespace occsweep {

/// How one scan's hits change a voxel (Algorithm 1 lines 3-10 for k-NN; one l(p_h) for OctoMap).
struct HitRule {
  enum class Kind : std::uint8_t {
    Constant,  ///< l_hit, whatever points the voxel holds (OctoMap)
    PointSum,  ///< the float sum of pointLogOdds over the voxel's in-range points in point order, clamped once to
               ///< [l_min, l_max] (Algorithm 1)
    PointMax,  ///< the largest pointLogOdds over the voxel's in-range points: one update, from its most reliable
               ///< point (OctoMap's one update per voxel and scan)
  };
  Kind kind = Kind::Constant;
  float l_hit = 0.0f;                                  ///< Constant
  std::shared_ptr<const PointFeature> feature;         ///< PointSum, PointMax: the feature pointLogOdds reads
  std::function<float(double)> pointLogOdds;           ///< PointSum, PointMax: l(p(feature)) of one point
};

/// A point filter (a removed point casts no ray and is no hit): a point is kept when its feature's score reaches
/// the threshold of its scan. Replayable because a voxel's event happens exactly when the largest score over the
/// points in it (hit) or over the rays that cross it (crossed) reaches the threshold (docs/methods.md, "Filters").
struct PointGate {
  std::shared_ptr<const PointFeature> feature;
  std::function<double(const FeatureScanSummary&)> threshold;  ///< per scan; -inf keeps every point
};

/// How one map's voxels change: every update is OctoMap's clamped one (Eq. 5), in the order of VoxelUpdateRule.
struct MapRule {
  float l_min = 0.0f, l_max = 0.0f;  ///< l(p_min), l(p_max)
  VoxelUpdateRule<float> update;     ///< l_in, l_out, the variant
  HitRule hit;
  std::optional<PointGate> gate;     ///< filters only; needs a Constant hit
};

/// What a rule may take from the sweep rather than from the grid.
struct RuleContext {
  MapSettings map;  ///< the sweep's settings (a rule reads the variant; its features may read s_c, the stats mode)
};

/// The values of one map's parameters, in the order of MappingMethod::parameters().
using MethodValues = std::vector<double>;

/// What a direct build needs besides the values (sweep settings; features are computed on demand).
struct MapContext {
  MapSettings map;
  /// Where the maps of a sweep share what they compute from the set, by identity (the direct engine holds one);
  /// none: a build computes its own.
  FeatureCache* shared = nullptr;
  /// Where a method may run its per-scan work in parallel (the same map whatever it does); empty: this thread.
  ScanExecutor executor;
};

/// The interface every method implements (docs/methods.md, "Bring your own method").
class MappingMethod {
 public:
  virtual ~MappingMethod() = default;

  /// The registered name: grid files' "method", results' grid.method.
  [[nodiscard]] virtual std::string name() const = 0;
  /// The name a paper's table or figure shows; by default the registered name.
  [[nodiscard]] virtual std::string displayName() const { return name(); }
  /// One line for `occsweep methods`.
  [[nodiscard]] virtual std::string description() const = 0;
  /// Where the model comes from (docs/methods.md cites it in full).
  [[nodiscard]] virtual std::string reference() const = 0;
  /// Every parameter but p_t, in the order grids enumerate them (the outermost first). Every method has p_max and
  /// p_min: the clamping thresholds, between which p_t runs.
  [[nodiscard]] virtual std::vector<MethodParameter> parameters() const = 0;
  /// The relations that must hold among the values of one map; grids skip the combinations that break one.
  [[nodiscard]] virtual std::vector<ParameterRelation> relations() const = 0;
  /// The parameters the hit rule and the gate's feature depend on: maps replayed together (lanes) share them.
  [[nodiscard]] virtual std::vector<std::string> sharedByLanes() const { return {}; }
  /// How a map with these values updates its voxels.
  [[nodiscard]] virtual MapRule rule(const MethodValues& values, const RuleContext& context) const = 0;
  /// The map built directly, the reference replay is tested against. By default the rule applied scan by scan
  /// through OcTree::updateNode (method_mapper.hpp); OctoMap and its filters use liboctomap itself.
  [[nodiscard]] virtual std::unique_ptr<octomap::OcTree> buildMap(const PointCloudSet& set, const MethodValues& values,
                                                                  const MapContext& context) const;
};

/// The index of parameter `name` in `method`'s parameters; std::invalid_argument naming both when it has none.
[[nodiscard]] std::size_t parameterIndex(const MappingMethod& method, const std::string& name);
/// The value of parameter `name` among `values`.
[[nodiscard]] double parameterValue(const MappingMethod& method, const MethodValues& values, const std::string& name);
/// Every parameter at its default value.
[[nodiscard]] MethodValues defaultValues(const MappingMethod& method);
/// The first bound or relation `values` break, as a sentence naming it; none if every one holds.
[[nodiscard]] std::optional<std::string> brokenRelation(const MappingMethod& method, const MethodValues& values);

// ---------------------------------------------------------------------------------------------------------

inline std::size_t parameterIndex(const MappingMethod& method, const std::string& name) {
  if (const std::optional<std::size_t> i = findParameter(method.parameters(), name)) return *i;
  throw std::invalid_argument("method " + method.name() + " has no parameter " + name);
}

inline double parameterValue(const MappingMethod& method, const MethodValues& values, const std::string& name) {
  return values.at(parameterIndex(method, name));
}

inline MethodValues defaultValues(const MappingMethod& method) {
  MethodValues values;
  for (const MethodParameter& p : method.parameters()) values.push_back(p.default_value);
  return values;
}

inline std::optional<std::string> brokenRelation(const MappingMethod& method, const MethodValues& values) {
  const std::vector<MethodParameter> parameters = method.parameters();
  if (values.size() != parameters.size())
    return method.name() + " takes " + std::to_string(parameters.size()) + " parameters, not " +
           std::to_string(values.size());
  return brokenRelation(parameters, method.relations(), values);
}

}  // namespace occsweep

#include "method_mapper.hpp"  // MappingMethod::buildMap's default: the rule through OcTree::updateNode
