// The two sweep engines and their factory (sweep_engine.hpp).
#include "occsweep/sweeps/sweep_engine.hpp"

#include <map>
#include <set>
#include <tuple>

#include <tbb/parallel_for.h>

#include "occsweep/core/enum_names.hpp"
#include "occsweep/core/knn_inverse_sensor_model.hpp"
#include "occsweep/core/octomap_baseline.hpp"
#include "occsweep/sweeps/replay.hpp"

namespace occsweep {
namespace {

enum class EngineKind { Replay, Direct };

constexpr EnumNames<EngineKind, 2> kEngineNames{
    "engine", {{{EngineKind::Replay, "replay"}, {EngineKind::Direct, "direct"}}}};

// The k of the maps, each once, ascending.
std::vector<int> distinctK(const std::vector<MapToCount>& maps) {
  std::set<int> ks;
  for (const MapToCount& m : maps) ks.insert(m.params->k);
  return {ks.begin(), ks.end()};
}

// Records the region voxels' events once and replays each map from them (replay.hpp).
class ReplayEngine final : public SweepEngine {
 public:
  std::string name() const override { return kEngineNames.text(EngineKind::Replay); }

  void prepare(const SweepInputs& in, const std::vector<MapToCount>& maps) override {
    const SweepConfig& c = in.config;
    knn_ = in.method == GridMethod::Knn;
    variant_ = c.variant;
    observable_ = c.truth == TruthMode::Observable;
    recorded_ = recordSet(in.scans, in.marked, c.resolution, c.s_c);
    // Replay needs only F(s) of the recorded hits: one k at a time, its distances freed at once (memory, issue 5).
    if (knn_)
      for (int k : distinctK(maps)) cdf_[k] = hitCdf(recorded_, parallelKnnDistances(in.scans, k, c.s_c), c.stats);
    // From here on only the recorded events are read: the points (12 bytes each) make room for replay's buffers.
    PointCloudSet().swap(in.scans);
  }

  std::vector<std::vector<std::size_t>> batches(const std::vector<MapToCount>& maps) const override {
    std::map<std::tuple<int, Fixed, Fixed>, std::vector<std::size_t>> groups;  // by hit rule
    for (std::size_t i = 0; i < maps.size(); ++i)
      groups[std::make_tuple(maps[i].params->k, maps[i].params->p_u, maps[i].params->p_l)].push_back(i);
    std::vector<std::vector<std::size_t>> out;
    for (auto& [_, members] : groups)
      for (std::size_t b = 0; b < members.size(); b += kReplayLanes)
        out.emplace_back(members.begin() + long(b),
                         members.begin() + long(std::min(b + kReplayLanes, members.size())));
    return out;
  }

  BatchCounts count(const std::vector<MapToCount>& maps, const std::vector<std::size_t>& batch) const override {
    std::vector<float> hit_sums;
    const MapParams& first = *maps[batch[0]].params;
    if (knn_) hit_sums = knnHitSums(recorded_, cdf_.at(first.k), toDouble(first.p_u), toDouble(first.p_l));
    std::vector<ReplayRule> rules;
    std::vector<std::vector<double>> p_t;
    for (std::size_t i : batch) {
      rules.push_back(knn_ ? knnRule(*maps[i].params, hit_sums, variant_) : octomapRule(*maps[i].params));
      p_t.push_back(maps[i].p_t);
    }
    // Without excluded voxels (full truth, no twin) both outputs are equal.
    BatchCounts out;
    out.counts = replayCounts(recorded_, rules, p_t, &out.observable);
    if (observable_) out.counts.swap(out.observable);
    return out;
  }

 private:
  bool knn_ = false, observable_ = false;
  UpdateVariant variant_ = UpdateVariant::Default;
  RecordedSet recorded_;
  std::map<int, std::vector<double>> cdf_;  // F(s) of every recorded hit, per k
};

// Builds every map: liboctomap for OctoMap, the k-NN mapper (the reference the replay engine is tested against).
class DirectEngine final : public SweepEngine {
 public:
  std::string name() const override { return kEngineNames.text(EngineKind::Direct); }

  void prepare(const SweepInputs& in, const std::vector<MapToCount>& maps) override {
    config_ = &in.config;
    knn_ = in.method == GridMethod::Knn;
    scans_ = &in.scans;
    truth_ = &in.truth;
    marked_ = in.twin ? &in.marked : nullptr;
    if (!knn_) return;
    // The distances of each k depend only on the points, k and s_c: shared by every map of that k.
    const std::vector<int> ks = distinctK(maps);
    for (int k : ks) distances_[k];
    tbb::parallel_for(std::size_t(0), ks.size(), [&](std::size_t i) {
      distances_[ks[i]] = parallelKnnDistances(*scans_, ks[i], config_->s_c);
    });
  }

  std::vector<std::vector<std::size_t>> batches(const std::vector<MapToCount>& maps) const override {
    std::vector<std::vector<std::size_t>> out;
    for (std::size_t i = 0; i < maps.size(); ++i) out.push_back({i});
    return out;
  }

  BatchCounts count(const std::vector<MapToCount>& maps, const std::vector<std::size_t>& batch) const override {
    BatchCounts out;
    for (std::size_t i : batch) {
      const MapParams& m = *maps[i].params;
      const auto tree = knn_ ? KnnInverseSensorModel(knnParams(m, *config_, m.p_min)).buildMap(*scans_,
                                                                                              distances_.at(m.k))
                             : buildOctoMap(*scans_, octomapParams(m, *config_, m.p_min));
      out.counts.push_back(classify(sampleRegion(*tree, *truth_), maps[i].p_t));
      if (marked_) out.observable.push_back(classify(sampleRegion(*tree, *marked_), maps[i].p_t));
    }
    return out;
  }

 private:
  const SweepConfig* config_ = nullptr;
  bool knn_ = false;
  const PointCloudSet* scans_ = nullptr;
  const GroundTruth* truth_ = nullptr;
  const GroundTruth* marked_ = nullptr;  // with a twin only
  std::map<int, KnnSetDistances> distances_;
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
