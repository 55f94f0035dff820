// The two sweep engines and their factory (sweep_engine.hpp). Neither knows any method: each asks the method for
// its rule (replay) or its map (direct) (docs/methods.md).
#include "occsweep/sweeps/sweep_engine.hpp"

#include <map>
#include <memory>
#include <utility>

#include "occsweep/core/enum_names.hpp"
#include "occsweep/sweeps/replay.hpp"
#include "occsweep/sweeps/tbb_scan_executor.hpp"

namespace occsweep {
namespace {

enum class EngineKind { Replay, Direct };

constexpr EnumNames<EngineKind, 2> kEngineNames{
    "engine", {{{EngineKind::Replay, kReplayEngine}, {EngineKind::Direct, kDirectEngine}}}};  // results.hpp

MethodValues valuesOf(const MapParams& m) {
  MethodValues v;
  for (Fixed x : m.values) v.push_back(toDouble(x));
  return v;
}

// The maps that may be replayed together: those with equal values of the method's sharedByLanes parameters, in
// the order of their first map; each group's maps in order.
std::vector<std::vector<std::size_t>> laneGroups(const MappingMethod& method, const ParameterLayout& layout,
                                                 const std::vector<MapToCount>& maps) {
  std::vector<std::size_t> shared;
  for (const std::string& name : method.sharedByLanes()) shared.push_back(layout.index(name));
  std::map<std::vector<Fixed>, std::vector<std::size_t>> groups;
  for (std::size_t i = 0; i < maps.size(); ++i) {
    std::vector<Fixed> key;
    for (std::size_t s : shared) key.push_back(maps[i].params->values[s]);
    groups[key].push_back(i);
  }
  std::vector<std::vector<std::size_t>> out;
  for (auto& [_, members] : groups) out.push_back(std::move(members));
  return out;
}

// Records the region voxels' events once and replays each map from them (replay.hpp).
class ReplayEngine final : public SweepEngine {
 public:
  std::string name() const override { return kEngineNames.text(EngineKind::Replay); }

  void prepare(const SweepInputs& in, const std::vector<GridMaps>& grids) override {
    const SweepConfig& c = in.config;
    grids_ = grids;
    context_ = {c.map};
    observable_ = c.truth == TruthMode::Observable;
    twin_ = in.twin;
    // What the maps of every grid need per point: one rule per lane group tells (the groups share their features).
    Features hit_needs, gate_needs;
    lane_groups_.clear();
    for (std::size_t g = 0; g < grids.size(); ++g) {
      auto& groups = lane_groups_.emplace_back();
      for (auto& maps : laneGroups(*grids[g].method, *grids[g].layout, *grids[g].maps)) {
        const MapRule rule = ruleOf(g, maps.front());
        if (rule.hit.kind != HitRule::Kind::Constant) hit_needs.emplace(rule.hit.feature->identity(), rule.hit.feature);
        if (rule.gate) gate_needs.emplace(rule.gate->feature->identity(), rule.gate->feature);
        groups.push_back({std::move(maps), rule.hit.kind != HitRule::Kind::Constant});
      }
    }
    recordWithGates(in, gate_needs);
    // Replay needs a hit feature only at the recorded hits: one feature at a time, freed at once (memory).
    for (const auto& [identity, feature] : hit_needs)
      hit_features_[identity] = recordedHitFeatures(recorded_, in.scans, *feature, c.map.s_c);
    // From here on only the recorded events are read: the points (12 bytes each) make room for replay's buffers.
    PointCloudSet().swap(in.scans);
  }

  // Batches of one lane group, of equal size (then cut at kBatchThresholds), replayed in passes of
  // kReplayPassLanes: up to kPassesPerBatch passes where the hit rule reads the points (a batch computes its events'
  // hits, a log per recorded hit, once for all its passes), one pass otherwise (nothing to share: smaller batches
  // spread a grid over more threads).
  // docs/performance.md, "Replay counting".
  static constexpr std::size_t kPassesPerBatch = 4;
  // A batch's thresholds at most (but one map at least): about 150 bytes each are held while a batch is counted and
  // written (its counts, results and curve), so a grid of a million thresholds per map costs one map's worth per
  // thread, not a lane group's (docs/robustness.md, "Limits"). Shipped grids have 9 per map: never cut.
  static constexpr std::size_t kBatchThresholds = std::size_t(1) << 18;

  std::vector<std::vector<std::size_t>> batches(std::size_t grid) const override {
    std::vector<std::vector<std::size_t>> out;
    const std::vector<MapToCount>& maps = *grids_.at(grid).maps;
    for (const LaneGroup& group : lane_groups_.at(grid)) {
      const std::size_t n = group.maps.size(), most = (group.reads_points ? kPassesPerBatch : 1) * kReplayPassLanes;
      const std::size_t count = (n + most - 1) / most, size = (n + count - 1) / count;
      for (std::size_t b = 0; b < n; b += size) {
        // Cut where the batch's thresholds pass kBatchThresholds: a batch's counts and results are held at once.
        std::vector<std::size_t> batch;
        std::size_t thresholds = 0;
        for (std::size_t i = b; i < std::min(b + size, n); ++i) {
          const std::size_t t = maps[group.maps[i]].p_t.size();
          if (!batch.empty() && thresholds + t > kBatchThresholds) {
            out.push_back(std::exchange(batch, {}));
            thresholds = 0;
          }
          batch.push_back(group.maps[i]);
          thresholds += t;
        }
        out.push_back(std::move(batch));
      }
    }
    return out;
  }

  BatchCounts count(std::size_t grid, const std::vector<std::size_t>& batch) const override {
    const std::vector<MapToCount>& maps = *grids_.at(grid).maps;
    std::vector<MapRule> rules;
    for (std::size_t i : batch) rules.push_back(ruleOf(grid, i));
    const MapRule& first = rules.front();
    std::vector<float> event_hits;
    if (first.hit.kind != HitRule::Kind::Constant)
      event_hits = eventHits(recorded_, hit_features_.at(first.hit.feature->identity()), first.hit);
    std::vector<ReplayRule> lanes;
    std::vector<std::vector<double>> p_t;
    for (std::size_t l = 0; l < batch.size(); ++l) {
      lanes.push_back(replayRule(rules[l], &event_hits));
      p_t.push_back(maps[batch[l]].p_t);
    }
    // Without excluded voxels (full truth, no twin) both outputs are equal: only the one used is counted (a map of a
    // million thresholds holds 32 MB of counts per truth).
    BatchCounts out;
    std::vector<std::vector<ConfusionCounts>>* observable = observable_ || twin_ ? &out.observable : nullptr;
    if (first.gate)
      out.counts = replayGatedCounts(recorded_, lanes, gate_columns_.at(first.gate->feature->identity()),
                                     laneGates(rules), p_t, observable);
    else
      out.counts = replayCounts(recorded_, lanes, p_t, observable);
    if (observable_) out.counts.swap(out.observable);
    return out;
  }

 private:
  // The features the maps ask for, each once (by identity).
  using Features = std::map<FeatureIdentity, std::shared_ptr<const PointFeature>>;

  MapRule ruleOf(std::size_t grid, std::size_t map) const {
    return grids_[grid].method->rule(valuesOf(*(*grids_[grid].maps)[map].params), context_);
  }

  // The events, with the extremes of every gate feature's scores (filters: docs/methods.md, "Filters").
  void recordWithGates(const SweepInputs& in, const Features& gate_needs) {
    const SweepConfig& c = in.config;
    SetGateScores scores;
    for (const auto& [identity, gate] : gate_needs) {
      SetFeature feature = gate->compute(in.scans, tbbScanExecutor());
      gate_columns_[identity] = scores.size();
      gate_summaries_.push_back(std::move(feature.summaries));
      auto& column = scores.emplace_back(feature.values.size());
      for (std::size_t t = 0; t < column.size(); ++t) column[t].assign(feature.values[t].begin(), feature.values[t].end());
    }
    recorded_ = recordSet(in.scans, in.marked, c.map.resolution, c.map.s_c, scores);
  }

  // Per lane, per scan: the gate's threshold for that scan's summary.
  LaneGates laneGates(const std::vector<MapRule>& rules) const {
    LaneGates gates;
    for (const MapRule& rule : rules) {
      const auto& summaries = gate_summaries_.at(gate_columns_.at(rule.gate->feature->identity()));
      auto& lane = gates.emplace_back();
      for (const FeatureScanSummary& s : summaries) lane.push_back(rule.gate->threshold(s));
    }
    return gates;
  }

  std::vector<GridMaps> grids_;
  // One lane group's maps, and whether its hit rule reads the points (eventHits).
  struct LaneGroup {
    std::vector<std::size_t> maps;
    bool reads_points = false;
  };
  std::vector<std::vector<LaneGroup>> lane_groups_;  // per grid (computed once: 249,200 maps take 1 s)
  RuleContext context_;
  bool observable_ = false;
  bool twin_ = false;  ///< SweepInputs::twin: the observable-truth counts go to a second file
  RecordedSet recorded_;
  std::map<FeatureIdentity, std::vector<double>> hit_features_;  // per hit feature: its value at every recorded hit
  std::map<FeatureIdentity, std::size_t> gate_columns_;           // per gate feature: its recorded column
  std::vector<std::vector<FeatureScanSummary>> gate_summaries_;  // per column, per scan
};

// Builds every map with the method's own builder (MappingMethod::buildMap: by default the rule applied through
// OcTree::updateNode, the reference the replay engine is tested against), sharing what the maps compute from the
// set through one FeatureCache.
class DirectEngine final : public SweepEngine {
 public:
  std::string name() const override { return kEngineNames.text(EngineKind::Direct); }

  void prepare(const SweepInputs& in, const std::vector<GridMaps>& grids) override {
    const SweepConfig& c = in.config;
    grids_ = grids;
    scans_ = &in.scans;
    truth_ = &in.truth;
    marked_ = in.twin ? &in.marked : nullptr;
    context_ = {c.map, &shared_, {}};
  }

  std::vector<std::vector<std::size_t>> batches(std::size_t grid) const override {
    std::vector<std::vector<std::size_t>> out;
    for (std::size_t i = 0; i < grids_.at(grid).maps->size(); ++i) out.push_back({i});
    return out;
  }

  BatchCounts count(std::size_t grid, const std::vector<std::size_t>& batch) const override {
    const std::vector<MapToCount>& maps = *grids_.at(grid).maps;
    BatchCounts out;
    for (std::size_t i : batch) {
      const auto tree = grids_[grid].method->buildMap(*scans_, valuesOf(*maps[i].params), context_);
      out.counts.push_back(classify(sampleRegion(*tree, *truth_), maps[i].p_t));
      if (marked_) out.observable.push_back(classify(sampleRegion(*tree, *marked_), maps[i].p_t));
    }
    return out;
  }

 private:
  std::vector<GridMaps> grids_;
  const PointCloudSet* scans_ = nullptr;
  const GroundTruth* truth_ = nullptr;
  const GroundTruth* marked_ = nullptr;  // with a twin only
  MapContext context_;
  mutable FeatureCache shared_;  // what the maps compute from the set, once each (MapContext::shared)
};

}  // namespace

std::vector<std::string> sweepEngineNames() { return kEngineNames.list(); }

std::unique_ptr<SweepEngine> makeSweepEngine(std::string_view name) {
  switch (kEngineNames.parse(name)) {
    case EngineKind::Replay:
      return std::make_unique<ReplayEngine>();
    case EngineKind::Direct:
      return std::make_unique<DirectEngine>();
  }
  throw std::logic_error("makeSweepEngine: an engine without a class");
}

}  // namespace occsweep
