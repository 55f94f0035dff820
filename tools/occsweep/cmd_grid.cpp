// occsweep grid count|list|shards GRID: the enumeration, Eq. 15 and the Eq. 16 split.
#include <iostream>
#include <optional>

#include "command_registry.hpp"
#include "option_checks.hpp"
#include "limit_options.hpp"
#include "occsweep/sweeps/grid.hpp"
#include "occsweep/sweeps/results.hpp"
#include "occsweep/sweeps/sharding.hpp"

namespace occsweep::cli {
namespace {

nlohmann::json paramsJson(const GridSpec& g, const MapParams& m, Fixed p_t) {
  MapResult params_only;
  params_only.params = m;
  nlohmann::json j = toJson(params_only, g.layout).at("params");
  j["p_t"] = toDouble(p_t);
  return j;
}

struct GridOptions {
  std::string grid;
  std::uint64_t groups = 20, seed = 0;
};

struct GridCommands {
  CLI::App *count, *list, *shards;
};

GridCommands addGridOptions(CLI::App& app, GridOptions& o) {
  const GridCommands subs{app.add_subcommand("count", "Print the enumeration count and Eq. 15's closed form"),
                          app.add_subcommand("list", "Print every combination with its stable id, as JSON lines"),
                          app.add_subcommand("shards", "Print the Eq. 16 split: a seeded permutation in groups")};
  for (CLI::App* sub : {subs.count, subs.list, subs.shards})
    sub->add_option("grid", o.grid, "Grid name (sweeps/grids) or path")->required();
  addExample(*subs.count, "occsweep grid count reduction --groups 20");
  addExample(*subs.list, "occsweep grid list octomap-opt");
  addExample(*subs.shards, "occsweep grid shards reduction --groups 20 --seed 0");
  for (CLI::App* sub : {subs.count, subs.list, subs.shards})
    addLimitOptions(*sub, {Limit::Combinations, Limit::JsonBytes});
  for (CLI::App* sub : {subs.count, subs.shards})
    sub->add_option("--groups", o.groups, "Number of groups N_d (Eq. 16)")->capture_default_str()->check(integerAtLeast<std::uint64_t>(1));
  subs.shards->add_option("--seed", o.seed, "Permutation seed")->capture_default_str();
  app.require_subcommand(1);
  return subs;
}

GridSpec loadNamedGrid(const GridOptions& o) { return loadGrid(resolveGridPath(o.grid)); }

int runGridCount(const GridOptions& o) {
  const GridSpec g = loadNamedGrid(o);
  // Eq. 15 counts without allocating; the enumeration, a cross-check, only within the limit. A method whose
  // relations are not a forest has no closed form: its maps are counted one by one (docs/grids.md, "Counting").
  const std::optional<std::uint64_t> eq15 = closedFormCount(g);
  const std::uint64_t closed = eq15 ? *eq15 : combinationCount(g);
  const char* how = eq15 ? "Eq. 15 closed form" : "counted map by map: no closed form for this method";
  if (closed >= kCountCeiling) {  // saturated: the exact count does not fit, and no group size is known
    std::cout << g.name << ": at least " << kCountCeiling << " combinations (" << how << "; the count passes 2^62)\n";
    return 0;
  }
  const bool enumerate = closed <= limits().combinations;
  const auto enumerated = enumerate ? enumerateGrid(g).combinations : closed;
  if (enumerate)
    std::cout << g.name << ": " << enumerated << " combinations (enumerated), " << closed << " (" << how << ")\n";
  else
    std::cout << g.name << ": " << closed << " combinations (" << how << "; not enumerated: more than "
              << "the limit of " << limits().combinations << ", --max-combinations)\n";
  const auto base = enumerated / o.groups, extra = enumerated % o.groups;
  std::cout << "per group of " << o.groups << " (Eq. 16): " << base;
  if (extra) std::cout << " (the first " << extra << " groups " << base + 1 << ")";
  std::cout << '\n';
  if (enumerated != closed) {
    std::cerr << "error: the enumeration and Eq. 15 disagree\n";
    return 1;
  }
  return 0;
}

int runGridList(const GridOptions& o) {
  const GridSpec g = loadNamedGrid(o);
  const GridEnumeration e = enumerateGrid(g);
  for (std::size_t m = 0; m < e.maps.size(); ++m)
    for (std::size_t t = 0; t < e.thresholds[m].size(); ++t)
      std::cout << nlohmann::json{{"id", e.first_id[m] + t}, {"map", m},
                                  {"params", paramsJson(g, e.maps[m], e.thresholds[m][t])}}
                       .dump()
                << '\n';
  return 0;
}

int runGridShards(const GridOptions& o) {
  const GridSpec g = loadNamedGrid(o);
  const auto n = combinationCount(g);
  // Each group's ids are listed, permuted over the whole grid: bounded as enumerating it is (docs/robustness.md,
  // "Limits").
  checkLimit("grid " + g.name + ": combinations", n, limits().combinations, "--max-combinations");
  for (std::uint64_t i = 0; i < o.groups; ++i) {
    const auto ids = permutationGroup(n, o.seed, o.groups, i);
    std::cout << nlohmann::json{{"group", i}, {"count", ids.size()}, {"ids", ids}}.dump() << '\n';
  }
  return 0;
}

const RegisterCommand kGrid{"grid", "Count, list or shard a parameter grid (Table 1, Eq. 11-16)", [](CLI::App& app) {
  auto o = std::make_shared<GridOptions>();
  const GridCommands subs = addGridOptions(app, *o);
  return [o, subs] {
    return runChosen({
        {subs.count, [&] { return runGridCount(*o); }},
        {subs.list, [&] { return runGridList(*o); }},
        {subs.shards, [&] { return runGridShards(*o); }},
    });
  };
}};

}  // namespace
}  // namespace occsweep::cli
