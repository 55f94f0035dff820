// The one home of each setting's names (UpdateVariant, StatsMode, TruthMode, the sweep engines): every value
// round-trips through its name, an unknown name is refused with the accepted ones, and the engine factory makes
// the two engines and nothing else.
#include <catch2/catch.hpp>

#include "occsweep/core/enum_names.hpp"
#include "occsweep/core/map_settings.hpp"
#include "occsweep/eval/observable_truth.hpp"
#include "occsweep/sweeps/replay.hpp"
#include "occsweep/core/method_registry.hpp"
#include "occsweep/sweeps/sweep_engine.hpp"

using namespace occsweep;
using Catch::Matchers::Equals;

namespace {

// The message of the std::invalid_argument `parse` throws; empty when it throws nothing (or something else).
template <class Parse>
std::string refusal(Parse&& parse) {
  try {
    (void)parse();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("update variant and statistics mode: the names of results files and the command line, both ways") {
  CHECK(std::string(toText(UpdateVariant::Default)) == "default");
  CHECK(std::string(toText(UpdateVariant::Literal)) == "literal");
  CHECK(std::string(toText(StatsMode::Batch)) == "batch");
  CHECK(std::string(toText(StatsMode::Online)) == "online");
  for (const UpdateVariant v : {UpdateVariant::Default, UpdateVariant::Literal}) CHECK(parseUpdateVariant(toText(v)) == v);
  for (const StatsMode s : {StatsMode::Batch, StatsMode::Online}) CHECK(parseStatsMode(toText(s)) == s);
  // CLI11's IsMember lists them in this order in --help.
  CHECK_THAT(kUpdateVariantNames.list(), Equals(std::vector<std::string>{"default", "literal"}));
  CHECK_THAT(kStatsModeNames.list(), Equals(std::vector<std::string>{"batch", "online"}));
}

TEST_CASE("an unknown variant, statistics mode or truth is refused naming the accepted names") {
  CHECK(refusal([] { return parseUpdateVariant("Literal"); }) == "variant 'Literal': must be default or literal");
  CHECK(refusal([] { return parseStatsMode(""); }) == "stats '': must be batch or online");
  CHECK(refusal([] { return parseTruthMode("observed"); }) == "truth 'observed': must be full or observable");
  // results check quotes them (docs/results-format.md, "a setting is not sane").
  CHECK(kUpdateVariantNames.alternatives("\"") == "\"default\" or \"literal\"");
  CHECK(kStatsModeNames.accepts("online"));
  CHECK_FALSE(kStatsModeNames.accepts("Online"));
}

TEST_CASE("truth mode names round-trip") {
  for (const TruthMode m : {TruthMode::Full, TruthMode::Observable}) CHECK(parseTruthMode(truthModeName(m)) == m);
  CHECK(std::string(truthModeName(TruthMode::Observable)) == "observable");
  CHECK_THAT(kTruthModeNames.list(), Equals(std::vector<std::string>{"full", "observable"}));
}

TEST_CASE("three or more names are listed as a, b or c") {
  enum class Colour { Red, Green, Blue };
  constexpr EnumNames<Colour, 3> names{"colour", {{{Colour::Red, "red"}, {Colour::Green, "green"}, {Colour::Blue, "blue"}}}};
  CHECK(refusal([&] { return names.parse("pink"); }) == "colour 'pink': must be red, green or blue");
  CHECK(names.parse("blue") == Colour::Blue);
}

TEST_CASE("the engine factory makes replay and direct, and refuses any other name") {
  CHECK_THAT(sweepEngineNames(), Equals(std::vector<std::string>{"replay", "direct"}));
  for (const std::string& name : sweepEngineNames()) CHECK(makeSweepEngine(name)->name() == name);
  CHECK(refusal([] { return makeSweepEngine("fast"); }) == "engine 'fast': must be replay or direct");
  CHECK(refusal([] { return makeSweepEngine("Replay"); }) == "engine 'Replay': must be replay or direct");
}

TEST_CASE("replay batches maps that share their hit rule, up to 64 when it reads the points, else 16, and direct one map each") {
  const ParameterLayout layout = layoutOf("knn");  // k, p_u, p_l, p_max, p_min, p_m, p_m_out
  MapParams a{{3 * kFixedScale, 860000, 260000, 980000, 20000, 400000, 450000}}, b = a;
  b.values[layout.index("p_u")] = 900000;  // another p_u: another hit rule
  std::vector<MapToCount> maps;
  for (int i = 0; i < 70; ++i) maps.push_back({&a, {0.5}});
  maps.push_back({&b, {0.5}});
  using Batches = std::vector<std::vector<std::size_t>>;
  // Batches are planned by prepare (here on a data set without scans, over a 2 x 2 x 2 region: nothing recorded).
  const SweepConfig config;
  PointCloudSet no_scans;
  const GroundTruth no_truth = makeGroundTruth({}, AxisBox{{0, 0, 0}, {0.2, 0.2, 0.2}}, 0.1);
  const SweepInputs inputs{config, no_scans, no_truth, no_truth, false};
  const auto batchesOf = [&](const char* engine) {
    const auto e = makeSweepEngine(engine);
    e->prepare(inputs, {{&findMethod("knn"), &layout, &maps}});
    return e->batches(0);
  };
  const auto range = [](std::size_t from, std::size_t to) {
    std::vector<std::size_t> out;
    for (std::size_t i = from; i < to; ++i) out.push_back(i);
    return out;
  };
  // 70 maps of one hit rule that reads the points: 2 batches of equal size, each at most 4 passes of 16 lanes.
  CHECK(batchesOf("replay") == Batches{range(0, 35), range(35, 70), {70}});
  Batches one_each;
  for (std::size_t i = 0; i <= 70; ++i) one_each.push_back({i});
  CHECK(batchesOf("direct") == one_each);
  static_assert(kReplayPassLanes == 16);

  // OctoMap's constant hit: nothing computed per batch, so one pass of at most 16 lanes each (20 maps: 2 x 10).
  const ParameterLayout octomap = layoutOf("octomap");
  MapParams o{std::vector<Fixed>(octomap.names.size(), 0)};
  for (const auto& [name, value] : {std::pair{"p_max", 980000}, {"p_min", 20000}, {"p_h", 700000}, {"p_m", 400000}})
    o.values[octomap.index(name)] = value;
  const std::vector<MapToCount> octomap_maps(20, {&o, {0.5}});
  const auto replay = makeSweepEngine("replay");
  replay->prepare(inputs, {{&findMethod("octomap"), &octomap, &octomap_maps}});
  CHECK(replay->batches(0) == Batches{range(0, 10), range(10, 20)});
}
