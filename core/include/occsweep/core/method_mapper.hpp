// Any method's map built directly from its rule (MappingMethod::buildMap's default): scan by scan, the kept
// points' events (scan_events.hpp), each voxel updated through OcTree::updateNode as VoxelUpdateRule orders it.
// It shares the rule with the replay engine but none of its code: the reference replay is tested against.
#pragma once

#include <algorithm>
#include <limits>
#include <memory>

#include <octomap/OcTree.h>

#include "mapping_method.hpp"
#include "occupancy_tree.hpp"
#include "scan_events.hpp"

namespace occsweep {

/// The map of `set` under `method` with `values`, built by applying method.rule() scan by scan.
[[nodiscard]] std::unique_ptr<octomap::OcTree> buildMapByRule(const MappingMethod& method, const PointCloudSet& set,
                                                              const MethodValues& values, const MapContext& context);

/// `feature` of every point of `set`: from the sweep's shared cache when the context has one (computed once for
/// every map), else computed here.
[[nodiscard]] std::shared_ptr<const SetFeature> featureOf(const PointFeature& feature, const PointCloudSet& set,
                                                         const MapContext& context);

/// The points of `scan` a gate keeps, in point order (all of them without a gate). Gate scores compare as float
/// (the replay engine records them as float).
[[nodiscard]] std::vector<std::uint32_t> keptPoints(const Scan& scan, const MapRule& rule, const std::vector<double>* scores,
                                                    const FeatureScanSummary& summary);

/// One voxel's hit delta from its points' features (HitRule: Constant, PointSum clamped once, PointMax).
template <class PointFeatures>
[[nodiscard]] float hitDeltaOf(const MapRule& rule, const PointFeatures& features);

// ---------------------------------------------------------------------------------------------------------

inline std::shared_ptr<const SetFeature> featureOf(const PointFeature& feature, const PointCloudSet& set,
                                                const MapContext& context) {
  if (!context.shared) return std::make_shared<const SetFeature>(feature.compute(set, context.executor));
  const auto compute = [&] { return std::make_shared<const SetFeature>(feature.compute(set, {})); };
  return context.shared->get<std::shared_ptr<const SetFeature>>(feature.identity(), compute);
}

inline std::vector<std::uint32_t> keptPoints(const Scan& scan, const MapRule& rule, const std::vector<double>* scores,
                                             const FeatureScanSummary& summary) {
  std::vector<std::uint32_t> kept;
  kept.reserve(scan.points.size());
  const double threshold = rule.gate ? rule.gate->threshold(summary) : 0.0;
  for (std::uint32_t i = 0; i < scan.points.size(); ++i)
    if (!rule.gate || double(float((*scores)[i])) >= threshold) kept.push_back(i);
  return kept;
}

template <class PointFeatures>
float hitDeltaOf(const MapRule& rule, const PointFeatures& features) {
  switch (rule.hit.kind) {
    case HitRule::Kind::Constant:
      return rule.hit.l_hit;
    case HitRule::Kind::PointSum: {
      float sum = 0.0f;  // float, in point order (Algorithm 1 lines 3-10), clamped once
      for (double f : features) sum += rule.hit.pointLogOdds(f);
      return std::min(std::max(sum, rule.l_min), rule.l_max);
    }
    case HitRule::Kind::PointMax: {
      float best = -std::numeric_limits<float>::infinity();
      for (double f : features) best = std::max(best, rule.hit.pointLogOdds(f));
      return best;
    }
  }
  return 0.0f;
}

inline std::unique_ptr<octomap::OcTree> buildMapByRule(const MappingMethod& method, const PointCloudSet& set,
                                                       const MethodValues& values, const MapContext& context) {
  if (auto why = brokenRelation(method, values)) throw std::invalid_argument(method.name() + ": " + *why);
  const MapRule rule = method.rule(values, {context.map});
  const bool point_hits = rule.hit.kind != HitRule::Kind::Constant;
  const auto none = std::make_shared<const SetFeature>();
  const auto hit_feature = point_hits ? featureOf(*rule.hit.feature, set, context) : none;
  const auto gate_feature = rule.gate ? featureOf(*rule.gate->feature, set, context) : none;
  auto tree = makeTree(context.map.resolution, parameterValue(method, values, "p_max"),
                       parameterValue(method, values, "p_min"), 0.5);
  ScanEventRecorder recorder(context.map.resolution);
  ScanEvents events;
  std::vector<double> features;
  for (std::size_t t = 0; t < set.size(); ++t) {
    // A removed point casts no ray and is no hit: the scan as the filter leaves it.
    const std::vector<std::uint32_t> kept =
        keptPoints(set[t], rule, rule.gate ? &gate_feature->values[t] : nullptr,
                   rule.gate ? gate_feature->summaries[t] : FeatureScanSummary{});
    Scan filtered{set[t].origin, {}, set[t].view};
    for (std::uint32_t i : kept) filtered.points.push_back(set[t].points[i]);
    const std::vector<std::uint32_t> inner = innerPoints(filtered, context.map.s_c);
    recorder.recordAll(filtered, inner, context.map.s_c, events);
    for (const VoxelEvent& e : events.voxels) {
      const auto hitDelta = [&] {
        features.clear();
        if (point_hits)
          for (std::uint32_t h = 0; h < e.hit_count; ++h)
            features.push_back(hit_feature->values[t][kept[inner[events.hit_points[e.first_hit + h]]]]);
        return hitDeltaOf(rule, features);
      };
      rule.update.apply(e.flags, hitDelta, [&](float delta) { tree->updateNode(e.key, delta); });
    }
  }
  return tree;
}

inline std::unique_ptr<octomap::OcTree> MappingMethod::buildMap(const PointCloudSet& set, const MethodValues& values,
                                                                const MapContext& context) const {
  return buildMapByRule(*this, set, values, context);
}

}  // namespace occsweep
