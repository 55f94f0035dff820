// occsweep grid count|list|shards GRID: the enumeration, Eq. 15 and the Eq. 16 split.
#include <iostream>

#include "command_registry.hpp"
#include "option_checks.hpp"
#include "limit_options.hpp"
#include "occsweep/sweeps/grid.hpp"
#include "occsweep/sweeps/sharding.hpp"

namespace occsweep::cli {
namespace {

nlohmann::json paramsJson(const GridSpec& g, const MapParams& m, Fixed p_t) {
  nlohmann::json j = {{"p_max", toDouble(m.p_max)}, {"p_min", toDouble(m.p_min)}, {"p_m", toDouble(m.p_m)}};
  if (g.method == GridMethod::Knn) {
    j["p_m_out"] = toDouble(m.p_m_out);
    j["p_u"] = toDouble(m.p_u);
    j["p_l"] = toDouble(m.p_l);
    j["k"] = m.k;
  } else {
    j["p_h"] = toDouble(m.p_h);
  }
  j["p_t"] = toDouble(p_t);
  return j;
}

const RegisterCommand kGrid{"grid", "Count, list or shard a parameter grid (Table 1, Eq. 11-16)", [](CLI::App& app) {
  auto grid = std::make_shared<std::string>();
  auto groups = std::make_shared<std::uint64_t>(20);
  auto seed = std::make_shared<std::uint64_t>(0);
  CLI::App* count = app.add_subcommand("count", "Print the enumeration count and Eq. 15's closed form");
  CLI::App* list = app.add_subcommand("list", "Print every combination with its stable id, as JSON lines");
  CLI::App* shards = app.add_subcommand("shards", "Print the Eq. 16 split: a seeded permutation in groups");
  for (CLI::App* sub : {count, list, shards})
    sub->add_option("grid", *grid, "Grid name (sweeps/grids) or path")->required();
  for (CLI::App* sub : {count, list, shards}) addLimitOptions(*sub, {Limit::Combinations});
  for (CLI::App* sub : {count, shards})
    sub->add_option("--groups", *groups, "Number of groups N_d (Eq. 16)")->capture_default_str()->check(integerAtLeast<std::uint64_t>(1));
  shards->add_option("--seed", *seed, "Permutation seed")->capture_default_str();
  app.require_subcommand(1);
  auto load = [grid] { return loadGrid(resolveGridPath(*grid)); };
  return [=] {
    return runChosen({
        {count, [=] {
           const GridSpec g = load();
           // Eq. 15 counts without allocating; the enumeration, a cross-check, only within the limit (issue 13).
           const auto closed = closedFormCount(g);
           const bool enumerate = closed <= limits().combinations;
           const auto enumerated = enumerate ? enumerateGrid(g).combinations : closed;
           if (enumerate)
             std::cout << g.name << ": " << enumerated << " combinations (enumerated), " << closed
                       << " (Eq. 15 closed form)\n";
           else
             std::cout << g.name << ": " << closed << " combinations (Eq. 15 closed form; not enumerated: more than "
                       << "the limit of " << limits().combinations << ", --max-combinations)\n";
           const auto base = enumerated / *groups, extra = enumerated % *groups;
           std::cout << "per group of " << *groups << " (Eq. 16): " << base;
           if (extra) std::cout << " (the first " << extra << " groups " << base + 1 << ")";
           std::cout << '\n';
           if (enumerated != closed) {
             std::cerr << "error: the enumeration and Eq. 15 disagree\n";
             return 1;
           }
           return 0;
         }},
        {list, [=] {
           const GridSpec g = load();
           const GridEnumeration e = enumerateGrid(g);
           for (std::size_t m = 0; m < e.maps.size(); ++m)
             for (std::size_t t = 0; t < e.thresholds[m].size(); ++t)
               std::cout << nlohmann::json{{"id", e.first_id[m] + t}, {"map", m},
                                           {"params", paramsJson(g, e.maps[m], e.thresholds[m][t])}}
                                .dump()
                         << '\n';
           return 0;
         }},
        {shards, [=] {
           const GridSpec g = load();
           const auto n = enumerateGrid(g).combinations;
           for (std::uint64_t i = 0; i < *groups; ++i) {
             const auto ids = permutationGroup(n, *seed, *groups, i);
             std::cout << nlohmann::json{{"group", i}, {"count", ids.size()}, {"ids", ids}}.dump() << '\n';
           }
           return 0;
         }},
    });
  };
}};

}  // namespace
}  // namespace occsweep::cli
