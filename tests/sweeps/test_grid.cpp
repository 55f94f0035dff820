// Grids: Table 1's counts, Eq. 15 against the enumeration on random grids, exact arithmetic, bad files, and the
// portable Eq. 16 permutation.
#include <catch2/catch.hpp>

#include <algorithm>
#include <set>
#include <sstream>

#include "occsweep/core/method_registry.hpp"
#include "occsweep/sweeps/grid.hpp"
#include "occsweep/sweeps/selection.hpp"
#include "occsweep/sweeps/sharding.hpp"
#include "test_helpers.hpp"

using namespace occsweep;
using Catch::Matchers::Contains;
using nlohmann::json;

TEST_CASE("Table 1's grids enumerate to the paper's counts and agree with Eq. 15") {
  const std::pair<const char*, std::uint64_t> expected[] = {{"reduction", 112500}, {"knn-opt", 4050}, {"octomap-opt", 180}};
  for (const auto& [name, count] : expected) {
    const GridSpec g = loadGrid(resolveGridPath(name));
    INFO(name);
    CHECK(enumerateGrid(g).combinations == count);
    CHECK(closedFormCount(g) == count);
  }
  for (std::uint64_t i = 0; i < 20; ++i) CHECK(permutationGroup(112500, 3, 20, i).size() == 5625);
}

TEST_CASE("occsweep grid count prints Table 1's counts beside Eq. 15, and grid list one line per stable id") {
  const auto count = [](const std::string& grid) {
    const auto r = test::runCli("grid count " + grid);
    REQUIRE(r.exit_code == 0);
    return r.output;
  };
  CHECK(count("reduction") ==
        "reduction: 112500 combinations (enumerated), 112500 (Eq. 15 closed form)\nper group of 20 (Eq. 16): 5625\n");
  CHECK(count("knn-opt") == "knn-opt: 4050 combinations (enumerated), 4050 (Eq. 15 closed form)\n"
                            "per group of 20 (Eq. 16): 202 (the first 10 groups 203)\n");
  CHECK(count("octomap-opt") ==
        "octomap-opt: 180 combinations (enumerated), 180 (Eq. 15 closed form)\nper group of 20 (Eq. 16): 9\n");

  // grid list: one JSON line per combination, ids 0..n-1 in order, parameters as the enumeration gives them.
  const auto r = test::runCli("grid list octomap-opt");
  REQUIRE(r.exit_code == 0);
  const GridEnumeration e = enumerateGrid(loadGrid(resolveGridPath("octomap-opt")));
  std::istringstream lines(r.output);
  std::string line;
  std::uint64_t id = 0;
  std::set<std::string> distinct;
  while (std::getline(lines, line)) {
    const json j = json::parse(line);
    REQUIRE(j.at("id").get<std::uint64_t>() == id);
    CHECK(j.at("params").at("p_t").get<double>() >= j.at("params").at("p_min").get<double>());
    distinct.insert(j.at("params").dump());
    ++id;
  }
  CHECK(id == e.combinations);
  CHECK(distinct.size() == e.combinations);  // no two ids name the same combination
}

TEST_CASE("grid values are exact: 0.98 is 0.98") {
  const GridSpec g = loadGrid(resolveGridPath("octomap-opt"));
  const auto p_h = g.range("p_h").values();
  REQUIRE(p_h.size() == 5);
  CHECK(p_h.back() == 980000);
  CHECK(toDouble(p_h.back()) == 0.98);
  const auto e = enumerateGrid(g);
  CHECK(e.thresholds[0].size() == 9);
  CHECK(toDouble(e.thresholds[0].back()) == 0.98);
  CHECK(toDouble(e.thresholds[0][1]) == 0.14);
}

namespace {

json randomRange(SplitMix64& rng, double lo, double hi, bool allow_value) {
  // Values in hundredths inside [lo, hi]; steps that may or may not divide the range.
  const int a = int(std::ceil(lo * 100)), b = int(std::floor(hi * 100));
  int x = a + int(rng.below(std::uint64_t(b - a + 1))), y = a + int(rng.below(std::uint64_t(b - a + 1)));
  if (x > y) std::swap(x, y);
  if (allow_value && rng.below(4) == 0) return {{"value", x / 100.0}};
  return {{"min", x / 100.0}, {"max", y / 100.0}, {"step", (1 + int(rng.below(20))) / 100.0}};
}

}  // namespace

TEST_CASE("Eq. 15's closed form equals the enumeration on randomly generated grid files") {
  for (std::uint64_t seed = 1; seed <= 300; ++seed) {
    SplitMix64 rng(seed);
    const bool knn = seed % 2 == 0;
    json j = {{"name", "random"}, {"method", knn ? "knn" : "octomap"}};
    json p = {{"p_max", randomRange(rng, 0.5, 0.99, true)},
              {"p_min", randomRange(rng, 0.01, 0.49, true)},
              {"p_m", randomRange(rng, 0.01, 0.49, true)},
              {"p_t", {{"step", (1 + int(rng.below(30))) / 100.0}}}};
    if (knn) {
      p["p_m_out"] = randomRange(rng, 0.01, 0.49, true);
      p["p_u"] = randomRange(rng, 0.01, 0.99, true);
      p["p_l"] = randomRange(rng, 0.01, 0.99, true);
      p["k"] = json::array();
      for (int k = 1; k <= 1 + int(rng.below(4)); ++k) p["k"].push_back(k * 2 - 1);
    } else {
      p["p_h"] = randomRange(rng, 0.5, 0.99, true);
    }
    j["parameters"] = p;
    const GridSpec g = parseGrid(j, "random.json");
    INFO("seed " << seed << " grid " << j.dump());
    CHECK(closedFormCount(g) == enumerateGrid(g).combinations);
  }
}

namespace {

// A random grid file of `method`: hundredths inside each parameter's bounds (within 1 of its lowest value), integer
// parameters as lists of a few values, p_t by a random step.
json randomGridOf(const MappingMethod& method, SplitMix64& rng) {
  json parameters = json::object();
  for (const MethodParameter& p : method.parameters()) {
    const double lo = p.lowest + (p.lowest_open ? 0.01 : 0.0);
    const double hi = std::min(p.highest - (p.highest_open ? 0.01 : 0.0), lo + 1.0);
    if (p.integer) {
      json list = json::array();
      for (int i = 0, n = 1 + int(rng.below(3)); i < n; ++i) list.push_back(std::llround(lo) + 2 * i);
      parameters[p.name] = list;
    } else {
      parameters[p.name] = randomRange(rng, lo, hi, true);
    }
  }
  parameters["p_t"] = {{"step", (1 + int(rng.below(30))) / 100.0}};
  return {{"name", "random"}, {"method", method.name()}, {"parameters", parameters}};
}

// A method whose relations join p_a and p_c twice (p_a >= p_b >= p_c and p_a >= p_c): not a forest.
class ChainedTwiceMethod final : public MappingMethod {
 public:
  std::string name() const override { return "test-chained-twice"; }
  std::string description() const override { return "test: relations that are not a forest"; }
  std::string reference() const override { return "tests/sweeps/test_grid.cpp"; }
  std::vector<MethodParameter> parameters() const override {
    return {{"p_a", "p_a", "", 0.6, 0, 1, true, true, false, "test"},
            {"p_b", "p_b", "", 0.5, 0, 1, true, true, false, "test"},
            {"p_c", "p_c", "", 0.4, 0, 1, true, true, false, "test"},
            {"p_max", "p_max", "upper clamp", 0.97, 0.5, 1, false, true, false, "Eq. 12"},
            {"p_min", "p_min", "lower clamp", 0.12, 0, 0.5, true, true, false, "Eq. 12"}};
  }
  std::vector<ParameterRelation> relations() const override {
    return {{"p_a", "p_b", false, "test"}, {"p_b", "p_c", false, "test"}, {"p_a", "p_c", true, "test"}};
  }
  MapRule rule(const MethodValues&, const RuleContext&) const override { return {}; }
};

}  // namespace

TEST_CASE("the closed form equals the enumeration for every registered method on 60 random grids each, and a "
          "method whose relations are not a forest is counted map by map") {
  // Old library: closedFormCount knew knn and octomap by name; every other method had none.
  for (const auto& method : registeredMethods()) {
    for (std::uint64_t seed = 1; seed <= 60; ++seed) {
      SplitMix64 rng(seed);
      const json j = randomGridOf(*method, rng);
      const GridSpec g = parseGrid(j, "random.json");
      INFO(method->name() << " seed " << seed << " grid " << j.dump());
      REQUIRE(closedFormCount(g).has_value());
      CHECK(*closedFormCount(g) == enumerateGrid(g).combinations);
      CHECK(combinationCount(g) == enumerateGrid(g).combinations);
    }
  }
  registerMethod(std::make_shared<ChainedTwiceMethod>());
  const MappingMethod& twice = findMethod("test-chained-twice");
  for (std::uint64_t seed = 1; seed <= 30; ++seed) {
    SplitMix64 rng(seed);
    const GridSpec g = parseGrid(randomGridOf(twice, rng), "random.json");
    CHECK_FALSE(closedFormCount(g).has_value());
    CHECK(combinationCount(g) == enumerateGrid(g).combinations);
  }
}

TEST_CASE("a shard's window of the grid selects exactly what the whole enumeration selects, on 200 random grids "
          "and shard counts") {
  // Old library: every sweep, shard or not, enumerated the whole grid first (a 398 M-combination grid ran out of
  // memory at 3 GB for a shard of 2,000).
  const auto methods = registeredMethods();
  for (std::uint64_t seed = 1; seed <= 200; ++seed) {
    SplitMix64 rng(seed);
    const MappingMethod& method = *methods[seed % methods.size()];
    const GridSpec g = parseGrid(randomGridOf(method, rng), "random.json");
    const GridEnumeration whole = enumerateGrid(g);
    SweepSelection s;
    s.shard_count = 1 + rng.below(std::max<std::uint64_t>(1, whole.maps.size() + 1));
    s.shard_index = rng.below(s.shard_count);
    INFO(method.name() << " seed " << seed << ": shard " << s.shard_index << "/" << s.shard_count << " of "
                       << whole.maps.size() << " maps");
    const GridEnumeration window = enumerateSelection(g, s);
    CHECK(window.combinations == whole.combinations);
    CHECK(window.map_count == whole.maps.size());
    CHECK(thresholdedMapCount(g) == whole.thresholded_maps);
    const auto expected = selectWork(g, whole, s), actual = selectWork(g, window, s);
    REQUIRE(actual.size() == expected.size());
    for (std::size_t i = 0; i < actual.size(); ++i) {
      CHECK(actual[i].map_index == expected[i].map_index);
      CHECK(actual[i].thresholds == expected[i].thresholds);
      CHECK(window.map(actual[i].map_index) == whole.maps[expected[i].map_index]);
      CHECK(window.firstId(actual[i].map_index) == whole.first_id[expected[i].map_index]);
      CHECK(window.thresholdsOf(actual[i].map_index) == whole.thresholds[expected[i].map_index]);
    }
    // It holds the shard's maps and nothing past them.
    CHECK(window.maps.size() <= whole.maps.size());
    if (!actual.empty()) CHECK(window.first_map == actual.front().map_index);
  }
}

TEST_CASE("bad grid files give a clear error naming the file and key") {
  json base = json::parse(R"({"name": "g", "method": "octomap", "parameters": {
      "p_max": {"value": 0.98}, "p_min": {"value": 0.02}, "p_h": {"min": 0.5, "max": 0.98, "step": 0.12},
      "p_m": {"min": 0.02, "max": 0.38, "step": 0.12}, "p_t": {"step": 0.12}}})");
  auto error = [&](auto edit) {
    json j = base;
    edit(j);
    try {
      (void)parseGrid(j, "bad.json");
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  CHECK(error([](json&) {}) == "accepted");
  CHECK_THAT(error([](json& j) { j["parameters"]["p_h"]["step"] = 0; }), Contains("bad.json") && Contains("p_h.step") && Contains("> 0"));
  CHECK_THAT(error([](json& j) { j["parameters"]["p_m"]["min"] = -0.02; }), Contains("p_m.min") && Contains("negative"));
  CHECK_THAT(error([](json& j) { j["parameters"]["p_h"]["min"] = 0.86; j["parameters"]["p_h"]["max"] = 0.62; }), Contains("p_h") && Contains("inverted"));
  CHECK_THAT(error([](json& j) { j["parameters"]["p_hit"] = 0.7; }), Contains("parameters.p_hit") && Contains("unknown key"));
  CHECK_THAT(error([](json& j) { j["colour"] = "red"; }), Contains("colour") && Contains("unknown key"));
  CHECK_THAT(error([](json& j) { j["parameters"]["p_max"] = {{"value", 1.0}}; }),
             Contains("parameters.p_max: values must lie in [0.5, 1) (Eq. 12)"));
  CHECK_THAT(error([](json& j) { j["parameters"]["p_t"]["step"] = 0; }), Contains("p_t.step"));
  CHECK_THAT(error([](json& j) { j["parameters"]["p_m"]["step"] = 0.1234567; }), Contains("6 decimals"));
  CHECK_THAT(error([](json& j) { j["parameters"].erase("p_m"); }), Contains("parameters.p_m") && Contains("missing"));
  CHECK_THAT(error([](json& j) { j["method"] = "knn"; }), Contains("unknown key"));  // p_h is not a k-NN parameter
  CHECK_THROWS_WITH(loadGrid("/nonexistent/grid.json"), Contains("/nonexistent/grid.json"));
}

TEST_CASE("the Eq. 16 permutation is a fixed, portable function of n and seed") {
  // SplitMix64's published output for seed 1234567 (Vigna's splitmix64.c): the generator is the reference one.
  SplitMix64 rng(1234567);
  CHECK(rng.next() == 6457827717110365317ull);
  CHECK(rng.next() == 3203168211198807973ull);
  CHECK(rng.next() == 9817491932198370423ull);
  // Pinned permutations, computed once by tools/shard_reference.py (Python, written from docs/grids.md): a change
  // to the algorithm, or a non-portable substitute such as std::shuffle, shows here even without python3.
  CHECK(portablePermutation(10, 42) == std::vector<std::uint64_t>{0, 9, 5, 8, 6, 4, 7, 2, 1, 3});
  CHECK(portablePermutation(20, 7) ==
        std::vector<std::uint64_t>{4, 1, 2, 15, 16, 18, 9, 6, 13, 3, 8, 5, 19, 12, 17, 10, 11, 0, 14, 7});
  CHECK(portablePermutation(10, 42) != portablePermutation(10, 43));
  for (std::uint64_t seed = 0; seed < 20; ++seed) {
    const std::uint64_t n = 1 + seed * 37, groups = 1 + seed % 7;
    std::vector<std::uint64_t> all;
    for (std::uint64_t g = 0; g < groups; ++g) {
      const auto ids = permutationGroup(n, seed, groups, g);
      CHECK(ids.size() == n / groups + (g < n % groups ? 1 : 0));  // the first n mod N_d groups one longer
      all.insert(all.end(), ids.begin(), ids.end());
    }
    std::sort(all.begin(), all.end());
    REQUIRE(all.size() == n);
    for (std::uint64_t i = 0; i < n; ++i) REQUIRE(all[i] == i);  // the union is the grid, each id once
  }
}

TEST_CASE("an independent program reproduces the permutation from the documented algorithm") {
  // tools/shard_reference.py implements docs/grids.md's description in Python; it must agree id for id.
  const auto dir = test::scratch("shard-reference");
  const std::string py = "/usr/bin/python3 " + (occsweep::test::sourceTree() / "tools").string() + "/shard_reference.py";
  const std::string ours = test::runCli("grid shards octomap-opt --groups 7 --seed 99").output;
  FILE* pipe = ::popen((py + " 180 99 7").c_str(), "r");
  REQUIRE(pipe);
  std::string theirs;
  char buf[4096];
  while (std::size_t n = std::fread(buf, 1, sizeof buf, pipe)) theirs.append(buf, n);
  REQUIRE(::pclose(pipe) == 0);
  CHECK(ours == theirs);
  CHECK(ours.size() > 100);
}
