// occsweep map: one map of a data set with any registered method, written as OctoMap's .ot (docs/methods.md,
// "One map"). Its parameters come from the method (defaults, bounds, relations), or, with --from, from a map a
// results file scored, whose stored counts the rebuilt map must reproduce.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>
#include <map>
#include <optional>
#include <set>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "command_registry.hpp"
#include "limit_options.hpp"
#include "map_setting_flags.hpp"
#include "option_checks.hpp"
#include "occsweep/core/method_registry.hpp"
#include "occsweep/data/map_file.hpp"
#include "occsweep/eval/confusion.hpp"
#include "occsweep/eval/coordinates.hpp"
#include "occsweep/eval/dataset.hpp"
#include "occsweep/sweeps/compare.hpp"
#include "occsweep/sweeps/map_recipe.hpp"
#include "occsweep/sweeps/results_verify.hpp"

namespace occsweep::cli {
namespace {

struct MapOptions {
  std::string dataset, out, method = "knn", from, truth = truthModeName(TruthMode::Full);
  MapSettingFlags map;
  double p_t = 0.5;
  bool force = false, best = false;
  std::optional<std::uint64_t> map_index;
  int threads = 0;
  std::map<std::string, double> values;             // every registered method's parameters by name, as given
  std::map<std::string, CLI::Option*> parameters;   // the flag of each of them
  std::map<std::string, CLI::Option*> settings;     // --method and the map settings: all taken from --from's file
};

// What the map is and how it is judged: from flags, or from a results file's map (--from).
struct MapRecipe {
  const MappingMethod* method = nullptr;
  MethodValues values;
  MapContext context;
  TruthMode truth = TruthMode::Full;
  std::vector<ThresholdResult> thresholds;  // the p_t to count at; with --from, the stored counts to reproduce
  std::optional<MapResult> stored;          // --from: the map as the results file holds it
};

std::string flagOf(const std::string& parameter) {
  std::string flag = "--" + parameter;
  std::replace(flag.begin(), flag.end(), '_', '-');
  return flag;
}

// What every method that has a parameter of this name allows: the widest closed bounds, integer if all say so.
// The flag refuses what none allows, naming the rule; the chosen method's own bounds and relations follow
// (brokenRelation).
struct ParameterFlag {
  std::vector<std::string> methods, meanings;  // each method's own words for it
  double lowest = 0, highest = 0;
  bool integer = true;
};

CLI::Validator flagRule(const ParameterFlag& f) {
  if (!f.integer) return numberIn(f.lowest, f.highest);
  return integerIn<long long>(std::llround(f.lowest), std::llround(f.highest));
}

// "hit: ... [octomap, sor-octomap; default: the method's]", or each method's words where they differ (--k).
std::string flagHelp(const ParameterFlag& f) {
  const auto same = [&](const std::string& m) { return m == f.meanings.front(); };
  if (std::all_of(f.meanings.begin(), f.meanings.end(), same)) {
    std::string of;
    for (const auto& m : f.methods) of += (of.empty() ? "" : ", ") + m;
    return f.meanings.front() + " [" + of + "; default: the method's]";
  }
  std::string help;
  for (std::size_t i = 0; i < f.methods.size(); ++i) help += (i ? "; " : "") + f.methods[i] + ": " + f.meanings[i];
  return help + " (default: the method's)";
}

// One flag per parameter name of every registered method (--p-h, --k, --std-mul, ...): a method takes the ones it
// has, its defaults fill the rest (`occsweep methods` lists them). Added after map's own flags: a parameter named
// like one of them (threads, from, max_points) is refused, naming both, for it would end every command at start-up
// (docs/methods.md, "One map"). The registry knows no flag: this check is the command's.
void addParameterFlags(CLI::App& app, MapOptions& o) {
  std::map<std::string, ParameterFlag> flags;
  for (const auto& m : registeredMethods())
    for (const MethodParameter& p : m->parameters()) {
      auto [it, fresh] = flags.try_emplace(p.name);
      ParameterFlag& f = it->second;
      f.methods.push_back(m->name());
      f.lowest = fresh ? p.lowest : std::min(f.lowest, p.lowest);
      f.highest = fresh ? p.highest : std::max(f.highest, p.highest);
      f.integer = f.integer && p.integer;
      f.meanings.push_back(p.meaning);
    }
  for (const auto& [name, f] : flags) {
    if (app.get_option_no_throw(flagOf(name)))
      throw std::invalid_argument("method " + f.methods.front() + ": parameter '" + name + "' would be `occsweep map " +
                                  flagOf(name) + "`, one of map's own flags: rename the parameter");
    o.parameters[name] = app.add_option(flagOf(name), o.values[name], flagHelp(f))->check(flagRule(f));
  }
}

std::vector<std::string> methodNames() {
  std::vector<std::string> names;
  for (const auto& m : registeredMethods()) names.push_back(m->name());
  return names;
}

void addMapOptions(CLI::App& app, MapOptions& o) {
  app.add_option("--dataset", o.dataset, "Data-set folder")->type_name(kPath)->required();
  app.add_option("--out", o.out, "Output map, .ot (written with MAP.ot.json; .bt is refused)")
      ->type_name(kPath)->required();
  app.add_flag("--force", o.force, "Replace occsweep's own previous map and settings at --out (nothing else)");
  o.settings["--method"] = app.add_option("--method", o.method, "Mapping method: " + registeredMethodNames())
                              ->check(CLI::IsMember(methodNames()))
                              ->capture_default_str();
  o.settings["--p-t"] = app.add_option("--p-t", o.p_t, "Occupancy threshold of the TP/FP/FN/TN summary (recorded in "
                                                       "MAP.ot.json; the .ot keeps log-odds only)")
                           ->capture_default_str()->check(probability());
  o.settings.merge(addMapSettingFlags(app, o.map));
  o.settings["--truth"] = app.add_option("--truth", o.truth, "Truth of the TP/FP/FN/TN summary: full, or observable (only "
                                                           "truth voxels a ray from a scan origin reaches within s_c "
                                                           "first; docs/results-format.md)")
                             ->check(CLI::IsMember(kTruthModeNames.list()))->capture_default_str();
  app.add_option("--from", o.from, "Rebuild a map a results file (.json or .db) scored, with every parameter and setting "
                                   "it stored; its counts must be reproduced at every p_t")->type_name(kPath)
      ->check(CLI::ExistingFile);
  app.add_flag("--best", o.best, "With --from: the map of the best AUC (as compare picks it)");
  app.add_option("--map-index", o.map_index, "With --from: the map of this index")
      ->check(integerIn<std::uint64_t>(0, std::numeric_limits<std::uint64_t>::max()));
  app.add_option("--threads", o.threads, "Worker threads of the build (0: all cores; the map is the same)")
      ->capture_default_str()->check(threadCount());
  addLimitOptions(app, {Limit::WindowVoxels, Limit::RegionVoxels, Limit::Points, Limit::NeighbourDistances,
                        Limit::JsonBytes});
  addParameterFlags(app, o);
}

bool given(const CLI::Option* option) { return option->count() > 0; }

// The values given by flag over the method's defaults; a flag the method has no parameter for is refused.
MethodValues valuesFromFlags(const MappingMethod& method, const MapOptions& o) {
  MethodValues values = defaultValues(method);
  std::set<std::string> own;
  for (const MethodParameter& p : method.parameters()) own.insert(p.name);
  for (const auto& [name, value] : o.values) {
    if (!given(o.parameters.at(name))) continue;
    if (!own.count(name))
      throw std::invalid_argument(flagOf(name) + ": method " + method.name() + " has no parameter " + name +
                                  " (`occsweep methods` lists each method's)");
    values[parameterIndex(method, name)] = value;
  }
  return values;
}

MapRecipe recipeFromFlags(const MapOptions& o) {
  if (o.best || o.map_index) throw std::invalid_argument("--best and --map-index choose a map of --from RESULTS");
  MapRecipe r;
  r.method = &findMethod(o.method);
  r.values = valuesFromFlags(*r.method, o);
  if (auto why = brokenRelation(*r.method, r.values))
    throw std::invalid_argument("--method " + o.method + ": " + *why +
                                "; a parameter no flag gives takes the method's default (occsweep methods)");
  // p_t as results keep it, to 1e-6 (docs/grids.md): the value checked is the value counted at.
  const Fixed p_t = Fixed(std::llround(o.p_t * double(kFixedScale)));
  const double p_max = parameterValue(*r.method, r.values, "p_max"), p_min = parameterValue(*r.method, r.values, "p_min");
  if (brokenThreshold(toDouble(p_t), p_min, p_max))
    throw std::invalid_argument("--p-t " + detail::fmt(toDouble(p_t)) + " (to 1e-6) must lie in [p_min, p_max] = [" +
                                detail::fmt(p_min) + ", " + detail::fmt(p_max) + "]");
  r.context.map = o.map.settings();
  r.truth = parseTruthMode(o.truth);
  r.thresholds.push_back({0, p_t, {}});
  return r;
}

// The map of the best AUC (compareBest's rule: the highest, ties to the lowest map index) or of --map-index, from
// one checked read of the file: what `results check` refuses is never rebuilt (docs/results-format.md, "Reading").
MapResult chosenMap(const MapOptions& o, ResultsHeader& header) {
  std::optional<MapResult> chosen;
  ResultsFile head;
  (void)readCheckedResults(o.from, "", [&](MapResult&& m) {
    const bool wanted = o.best ? isBetterBest(m.area.anchored, chosen ? std::optional(chosen->area.anchored)
                                                                       : std::nullopt)
                               : m.map_index == *o.map_index;
    if (wanted) chosen = std::move(m);
  }, &head);
  header = head.header;
  if (!chosen)
    throw std::invalid_argument("--from " + o.from + (o.best ? ": no map with an AUC" :
                                ": no map of index " + std::to_string(*o.map_index)));
  return *chosen;
}

MapRecipe recipeFromResults(const MapOptions& o, const std::string& dataset_hash) {
  if (o.best == o.map_index.has_value())
    throw std::invalid_argument("--from needs exactly one of --best and --map-index");
  for (const auto* flags : {&o.parameters, &o.settings})
    for (const auto& [key, option] : *flags)
      if (given(option))
        throw std::invalid_argument(option->get_name() + ": --from takes every parameter and setting from " + o.from +
                                    "; drop " + option->get_name());
  MapRecipe r;
  ResultsHeader header;
  r.stored = chosenMap(o, header);
  if (dataset_hash != header.dataset_hash)
    throw std::invalid_argument("--dataset " + o.dataset + " (content hash " + dataset_hash + ") is not the data set " + o.from +
                                " was swept on (" + header.dataset_name + ", " + header.dataset_hash + ")");
  ScoredMapRecipe scored = scoredMapRecipe(header, *r.stored, "--from " + o.from);
  r.method = scored.method;
  r.values = std::move(scored.values);
  r.context = std::move(scored.context);
  r.truth = header.truth;
  r.thresholds = r.stored->thresholds;
  return r;
}

// Every point beyond s_c only frees space (OctoMap's maxrange, Algorithm 1's out-of-range branch): say so, since
// the map then cannot hold an occupied voxel (docs/robustness.md, "Numbers that must not be wrong").
void warnWhenAllBeyondRange(const PointCloudSet& scans, double s_c) {
  double nearest = std::numeric_limits<double>::infinity();
  for (const auto& scan : scans)
    for (const auto& p : scan.points) nearest = std::min(nearest, rangeFromOrigin(p, scan.origin));
  if (nearest > s_c)
    std::cerr << "occsweep map: warning: every point is beyond s_c = " << s_c << " m (the nearest is " << nearest
              << " m from its sensor origin): no voxel can become occupied; raise --s-c\n";
}

// The method's build with its scans' work on `threads` TBB workers (0: all), in an arena of that many as `sweep`
// runs: the same map on any number (docs/architecture.md, "Threads"). liboctomap's own builds use one thread.
std::unique_ptr<octomap::OcTree> buildOnThreads(const MapRecipe& r, const PointCloudSet& scans, int threads) {
  tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
  return arena.execute([&] {
    MapContext context = r.context;
    context.executor.for_each = [](std::size_t count, const std::function<void(std::size_t)>& body) {
      tbb::parallel_for(std::size_t(0), count, [&](std::size_t t) { body(t); });
    };
    context.executor.concurrency = std::size_t(std::max(1, tbb::this_task_arena::max_concurrency()));
    return r.method->buildMap(scans, r.values, context);
  });
}

// The .ot keeps resolution and log-odds only: what built it goes beside it, in MAP.ot.json.
nlohmann::json mapSettings(const MapOptions& o, const MapRecipe& r, const Dataset& d, const std::string& dataset_hash,
                           double seconds) {
  nlohmann::json params = nlohmann::json::object();
  const std::vector<MethodParameter> parameters = r.method->parameters();
  for (std::size_t i = 0; i < parameters.size(); ++i)
    params[parameters[i].name] = parameters[i].integer ? nlohmann::json(std::llround(r.values[i])) : nlohmann::json(r.values[i]);
  if (!r.stored) params["p_t"] = toDouble(r.thresholds.front().p_t);
  params.update(toJson(r.context.map));
  nlohmann::json settings = {{"format", kMapSettingsFormat}, {"method", r.method->name()}, {"dataset", o.dataset},
                             {"dataset_name", d.name}, {"dataset_hash", dataset_hash},
                             {"parameters", params}, {"truth", truthModeName(r.truth)}, {"build_seconds", seconds}};
  if (r.stored) settings["from"] = {{"results", o.from}, {"map_index", r.stored->map_index}};
  return settings;
}

// Flags: the counts at --p-t. --from: the counts at every stored p_t, each equal to the stored ones, or exit 1.
int reportCounts(const MapRecipe& r, const octomap::OcTree& tree, const GroundTruth& truth, const MapOptions& o) {
  const RegionSample sample = sampleRegion(tree, truth);
  const char* truth_note = r.truth == TruthMode::Observable ? " (observable truth)" : "";
  int differing = 0;
  for (const ThresholdResult& stored : r.thresholds) {
    const ConfusionCounts c = classify(sample, toDouble(stored.p_t));
    if (!r.stored) {
      std::cout << "at p_t " << toDouble(stored.p_t) << truth_note << ": TP " << c.tp << " FP " << c.fp << " FN " << c.fn
                << " TN " << c.tn << "  TPR " << c.tpr() << " FDR " << c.fdr() << '\n';
    } else if (!(c == stored.counts)) {
      if (++differing <= 5)
        std::cout << "at p_t " << toDouble(stored.p_t) << ": TP " << c.tp << " FP " << c.fp << " FN " << c.fn << " TN "
                  << c.tn << ", stored TP " << stored.counts.tp << " FP " << stored.counts.fp << " FN "
                  << stored.counts.fn << " TN " << stored.counts.tn << '\n';
    }
  }
  if (!r.stored) return 0;
  std::cout << "map " << r.stored->map_index << " of " << o.from << " (AUC " << r.stored->area.anchored << truth_note
            << "): " << (differing == 0 ? "counts equal the stored ones at all " : "counts differ at ")
            << (differing == 0 ? r.thresholds.size() : std::size_t(differing)) << " of " << r.thresholds.size()
            << " thresholds\n";
  return differing == 0 ? 0 : 1;
}

int runMap(const MapOptions& o) {
  checkMapTarget(o.out, o.force);  // before any reading: a refused output costs nothing
  const std::string dataset_hash = datasetContentHash(o.dataset);
  const MapRecipe r = o.from.empty() ? recipeFromFlags(o) : recipeFromResults(o, dataset_hash);
  const Dataset d = readDataset(o.dataset);
  requireInKeyRange(d, o.dataset, r.context.map.resolution);
  warnWhenAllBeyondRange(d.scans, r.context.map.s_c);
  // The truth is built before the map: a region it cannot use (past its limit, no voxel) costs no build and leaves
  // no map.
  const bool has_truth = !d.truth.boxes.empty() || !d.truth.mesh.empty() || !d.truth.points.empty();
  if (r.stored && !has_truth) throw std::invalid_argument("--dataset " + o.dataset + " has no truth to count against");
  std::optional<GroundTruth> gt;
  if (has_truth)
    gt = evaluatedTruth(r.truth, groundTruthOf(d, o.dataset, r.context.map.resolution), d.scans, r.context.map.s_c,
                        o.dataset);
  const auto start = std::chrono::steady_clock::now();
  const auto tree = buildOnThreads(r, d.scans, o.threads);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  writeMapFile(*tree, mapSettings(o, r, d, dataset_hash, seconds), o.out);
  std::cout << "method " << r.method->name() << ", " << d.scans.size() << " scans, " << pointCount(d.scans)
            << " points, built in " << seconds << " s\n"
            << "map " << o.out << ": " << tree->getNumLeafNodes() << " leaves (settings in " << o.out << ".json)\n";
  return gt ? reportCounts(r, *tree, *gt, o) : 0;
}

const RegisterCommand kMap{"map", "Build one map of a data set and write it as OctoMap .ot (octovis opens it)",
                           [](CLI::App& app) {
  addExample(app, "occsweep map --dataset ds --method knn --k 3 --out knn.ot\n"
                  "occsweep map --dataset ds --from knn.json --best --out best.ot");
  auto o = std::make_shared<MapOptions>();
  addMapOptions(app, *o);
  return [o] { return runMap(*o); };
}};

}  // namespace
}  // namespace occsweep::cli
