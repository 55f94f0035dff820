// The replay engine's fast path (replay_lanes.cpp: maps in passes of up to kReplayPassLanes lanes, vectors of four
// floats, the Default variant's updates chosen by table instead of branches) against the plain single-lane replay()
// (replay.cpp: one float per voxel through clampedUpdate and VoxelUpdateRule<float>), on random recorded sets:
// every count of every lane identical. The sets are drawn to reach what the fast path treats apart: mixed and
// uniform voxels, every flags combination, hit deltas beyond the clamp bounds, -0, l_min >= l_max, events
// without flags, 1 to 40 lanes (one to three passes of every width), both variants, the three hit sources, gates.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "occsweep/core/log_odds.hpp"
#include "occsweep/core/splitmix64.hpp"
#include "occsweep/sweeps/replay.hpp"

using namespace occsweep;

namespace {

constexpr std::uint32_t kScans = 6;

// A log-odds drawn from a few that matter (0, -0, bounds of a probability grid) and from a wide range.
float someLogOdds(SplitMix64& rng) {
  switch (rng.below(6)) {
    case 0: return 0.0f;
    case 1: return -0.0f;
    case 2: return logOdds(0.02 + 0.12 * double(rng.below(9)));
    default: return float(12.0 * rng.uniform() - 6.0);
  }
}

// Events of one voxel: none, all alike (a table voxel), or mixed; flags 0 only where `flagless`.
void addVoxelEvents(SplitMix64& rng, bool flagless, RecordedSet& r) {
  const std::uint32_t n = rng.below(4) == 0 ? 0 : 1 + std::uint32_t(rng.below(rng.below(3) == 0 ? 90 : 12));
  const std::uint8_t alike = std::uint8_t(1 + rng.below(7));
  const bool uniform = rng.below(3) == 0;
  std::uint32_t scan = 0;
  for (std::uint32_t e = 0; e < n; ++e) {
    std::uint8_t f = uniform ? alike : std::uint8_t(1 + rng.below(7));
    if (flagless && rng.below(40) == 0) f = 0;
    r.flags.push_back(f);
    scan = std::min<std::uint32_t>(kScans - 1, scan + std::uint32_t(rng.below(2)));
    r.event_scan.push_back(scan);
    for (int x = 0; x < kExtremes; ++x)
      r.extremes.push_back(rng.below(5) == 0 ? -std::numeric_limits<float>::infinity() : float(rng.uniform()));
  }
  r.voxel_first.push_back(std::uint32_t(r.flags.size()));
}

// A recorded set as recordSet leaves it (truth, events by voxel, uniform flags, the longest list), one gate column.
RecordedSet randomSet(SplitMix64& rng, bool flagless) {
  RecordedSet r;
  const std::uint32_t voxels = 40 + std::uint32_t(rng.below(300));
  r.voxel_first.push_back(0);
  for (std::uint32_t v = 0; v < voxels; ++v) {
    const std::uint8_t t = std::uint8_t(rng.below(10) < 6 ? 0 : 1 + rng.below(2));
    r.truth.push_back(t);
    r.positives += t != 0, r.excluded += t == 2;
    addVoxelEvents(rng, flagless, r);
  }
  r.negatives = voxels - r.positives;
  r.uniform.assign(voxels, 0);
  for (std::uint32_t v = 0; v < voxels; ++v) {
    const std::uint32_t begin = r.voxel_first[v], end = r.voxel_first[v + 1];
    r.longest = std::max(r.longest, end - begin);
    bool alike = begin != end;
    for (std::uint32_t e = begin; e < end && alike; ++e) alike = r.flags[e] == r.flags[begin];
    r.uniform[v] = alike ? r.flags[begin] : 0;
  }
  r.gate_columns = 1;
  return r;
}

// One lane: its clamp bounds (sometimes equal or crossed), deltas and p_t values, some at its voxels' values.
struct RandomLane {
  ReplayRule rule;
  std::vector<double> p_t;
};

RandomLane randomLane(SplitMix64& rng, UpdateVariant variant, HitRule::Kind kind, const std::vector<float>* hits) {
  RandomLane lane;
  ReplayRule& rule = lane.rule;
  const float a = someLogOdds(rng), b = someLogOdds(rng);
  rule.l_min = std::min(a, b), rule.l_max = std::max(a, b);
  if (rng.below(10) == 0) rule.l_max = rule.l_min;
  if (rng.below(10) == 0) std::swap(rule.l_min, rule.l_max);  // l_min > l_max: no method makes it, exact anyway
  rule.update = {someLogOdds(rng), someLogOdds(rng), variant};
  rule.constant_hit = someLogOdds(rng);
  if (kind != HitRule::Kind::Constant) rule.event_hits = hits;
  rule.clamp_event_hits = kind == HitRule::Kind::PointSum;
  for (std::uint64_t i = 0, n = 1 + rng.below(12); i < n; ++i) lane.p_t.push_back(0.01 + 0.98 * rng.uniform());
  return lane;
}

// Thresholds at voxels' own values (and their float neighbours), where a wrong last bit changes a count.
void addThresholdsAtValues(SplitMix64& rng, const RegionSample& s, std::vector<double>& p_t) {
  for (const auto* values : {&s.positive_log_odds, &s.negative_log_odds})
    for (int i = 0; i < 4 && !values->empty(); ++i) {
      const float v = (*values)[rng.below(values->size())];
      const float near[3] = {v, std::nextafter(v, -INFINITY), std::nextafter(v, INFINITY)};
      const double p = probability(near[rng.below(3)]);
      if (p > 0.0 && p < 1.0) p_t.push_back(p);
    }
}

// The set as full truth counts it: excluded voxels are plain positives (replay() leaves excluded voxels out).
RecordedSet fullTruth(RecordedSet r) {
  for (auto& t : r.truth) t = t == 2 ? 1 : t;
  r.excluded = 0;
  return r;
}

// Lane l's view of a gated set: each event keeps the kinds whose extreme reaches the lane's gate for its scan, and
// an event that keeps none is gone (a written-out reading of docs/methods.md, "Filters", for the plain replay()).
RecordedSet gatedView(const RecordedSet& r, const std::vector<double>& gate) {
  RecordedSet g = r;
  g.voxel_first = {0}, g.flags.clear();
  const std::uint8_t kinds[kExtremes] = {kHit, kCrossedIn, kCrossedOut};
  for (std::size_t v = 0; v + 1 < r.voxel_first.size(); ++v) {
    for (std::uint32_t e = r.voxel_first[v]; e < r.voxel_first[v + 1]; ++e) {
      std::uint8_t kept = 0;
      for (int x = 0; x < kExtremes; ++x)
        if ((r.flags[e] & kinds[x]) && r.extremes[std::size_t(e) * kExtremes + std::size_t(x)] >= gate[r.event_scan[e]])
          kept |= kinds[x];
      if (kept) g.flags.push_back(kept);
    }
    g.voxel_first.push_back(std::uint32_t(g.flags.size()));
  }
  return g;
}

void requireLaneEqual(const std::vector<ConfusionCounts>& fast, const RegionSample& plain,
                      const std::vector<double>& p_t, const char* truth) {
  INFO(truth);
  const std::vector<ConfusionCounts> expected = classify(plain, p_t);
  REQUIRE(fast.size() == expected.size());
  for (std::size_t t = 0; t < p_t.size(); ++t) {
    INFO("p_t " << p_t[t] << ": fast tp " << fast[t].tp << " fp " << fast[t].fp << "; plain tp " << expected[t].tp
                << " fp " << expected[t].fp);
    REQUIRE(fast[t] == expected[t]);
  }
}

struct Draw {
  UpdateVariant variant;
  std::vector<RandomLane> lanes;
  std::vector<ReplayRule> rules() const {
    std::vector<ReplayRule> out;
    for (const RandomLane& l : lanes) out.push_back(l.rule);
    return out;
  }
  std::vector<std::vector<double>> p_t() const {
    std::vector<std::vector<double>> out;
    for (const RandomLane& l : lanes) out.push_back(l.p_t);
    return out;
  }
};

// Per event, the hit delta eventHits would give (0 where no hit).
std::vector<float> randomHits(SplitMix64& rng, const RecordedSet& r) {
  std::vector<float> hits;
  for (std::uint8_t f : r.flags) hits.push_back(f & kHit ? someLogOdds(rng) : 0.0f);
  return hits;
}

// 1 to 40 lanes of one variant and hit rule (`hits`: the events' hit deltas, kept by the caller).
Draw randomDraw(SplitMix64& rng, const RecordedSet& r, HitRule::Kind kind, const std::vector<float>& hits) {
  Draw d{rng.below(4) == 0 ? UpdateVariant::Literal : UpdateVariant::Default, {}};
  const std::size_t n = 1 + rng.below(40);
  for (std::size_t l = 0; l < n; ++l) d.lanes.push_back(randomLane(rng, d.variant, kind, &hits));
  for (RandomLane& l : d.lanes) addThresholdsAtValues(rng, replay(r, l.rule), l.p_t);
  return d;
}

}  // namespace

TEST_CASE("replayCounts equals the single-lane replay on 400 random recorded sets, every lane and threshold") {
  std::size_t lanes = 0, literal = 0, flagless = 0, crossed = 0;
  for (std::uint64_t seed = 1; seed <= 400; ++seed) {
    INFO("seed " << seed);
    SplitMix64 rng(seed);
    const RecordedSet r = randomSet(rng, seed % 5 == 0);
    const RecordedSet full = fullTruth(r);
    const auto kind = HitRule::Kind(rng.below(3));  // Constant, PointSum, PointMax
    const std::vector<float> hits = randomHits(rng, r);
    const Draw draw = randomDraw(rng, r, kind, hits);
    std::vector<std::vector<ConfusionCounts>> observable;
    const auto counts = replayCounts(r, draw.rules(), draw.p_t(), &observable);
    REQUIRE(counts.size() == draw.lanes.size());
    for (std::size_t l = 0; l < draw.lanes.size(); ++l) {
      INFO("lane " << l << " of " << draw.lanes.size() << ", hit kind " << int(kind));
      const RandomLane& lane = draw.lanes[l];
      requireLaneEqual(counts[l], replay(full, lane.rule), lane.p_t, "full truth");
      requireLaneEqual(observable[l], replay(r, lane.rule), lane.p_t, "observable truth");
      crossed += lane.rule.l_min > lane.rule.l_max;
    }
    lanes += draw.lanes.size();
    literal += draw.variant == UpdateVariant::Literal;
    flagless += std::count(r.flags.begin(), r.flags.end(), 0) > 0;
  }
  // The draws reached what they are meant to.
  CHECK(lanes > 4000);
  CHECK(literal > 50);
  CHECK(flagless > 20);
  CHECK(crossed > 100);
}

TEST_CASE("replayGatedCounts equals the single-lane replay of each lane's kept events on 300 random sets") {
  for (std::uint64_t seed = 1001; seed <= 1300; ++seed) {
    INFO("seed " << seed);
    SplitMix64 rng(seed);
    // No event without flags: the recorder never makes one, and a gate's "every lane keeps all" reads it as kept.
    const RecordedSet r = randomSet(rng, false);
    const std::vector<float> no_hits;  // a filter's hit is constant
    const Draw draw = randomDraw(rng, r, HitRule::Kind::Constant, no_hits);
    LaneGates gates;
    for (std::size_t l = 0; l < draw.lanes.size(); ++l) {
      auto& gate = gates.emplace_back();
      for (std::uint32_t t = 0; t < kScans; ++t) gate.push_back(rng.below(4) == 0 ? -1.0 : 1.2 * rng.uniform() - 0.1);
      // Some gates at a recorded extreme, or one double step beside it: a float bound of the gate must keep
      // exactly the extremes the double comparison keeps.
      for (std::uint32_t t = 0; t < kScans; ++t) {
        if (rng.below(3) != 0 || r.extremes.empty()) continue;
        const double at = r.extremes[rng.below(r.extremes.size())];
        const double beside[3] = {std::nextafter(at, -2.0), at, std::nextafter(at, 2.0)};
        gate[t] = beside[rng.below(3)];
      }
    }
    std::vector<std::vector<ConfusionCounts>> observable;
    const auto counts = replayGatedCounts(r, draw.rules(), 0, gates, draw.p_t(), &observable);
    REQUIRE(counts.size() == draw.lanes.size());
    for (std::size_t l = 0; l < draw.lanes.size(); ++l) {
      INFO("lane " << l << " of " << draw.lanes.size());
      const RecordedSet kept = gatedView(r, gates[l]);
      requireLaneEqual(counts[l], replay(fullTruth(kept), draw.lanes[l].rule), draw.lanes[l].p_t, "full truth");
      requireLaneEqual(observable[l], replay(kept, draw.lanes[l].rule), draw.lanes[l].p_t, "observable truth");
    }
  }
}

TEST_CASE("replayCounts refuses lanes that do not share their hit rule, and empty lanes") {
  std::vector<float> hits_a, hits_b;
  RecordedSet r;
  r.voxel_first = {0};
  ReplayRule a, b;
  a.event_hits = &hits_a, b.event_hits = &hits_b;
  CHECK_THROWS_AS(replayCounts(r, {a, b}, {{0.5}, {0.5}}), std::invalid_argument);
  CHECK_THROWS_AS(replayCounts(r, {}, {}), std::invalid_argument);
  CHECK_THROWS_AS(replayCounts(r, {a}, {{0.5}, {0.5}}), std::invalid_argument);
}
