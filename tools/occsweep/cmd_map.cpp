// occsweep map: one map of a data set with OctoMap or the k-NN model, written as OctoMap's .ot.
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <limits>
#include <unistd.h>

#include <tbb/task_arena.h>

#include "command_registry.hpp"
#include "option_checks.hpp"
#include "limit_options.hpp"
#include "occsweep/core/knn_inverse_sensor_model.hpp"
#include "occsweep/core/octomap_baseline.hpp"
#include "occsweep/eval/coordinates.hpp"
#include "occsweep/eval/dataset.hpp"
#include "occsweep/eval/confusion.hpp"
#include "occsweep/sweeps/replay.hpp"
#include "occsweep/sweeps/results.hpp"

namespace occsweep::cli {
namespace {

struct MapOptions {
  std::string dataset, out, method = "knn", variant = toText(UpdateVariant::Default), stats = toText(StatsMode::Batch),
              truth = truthModeName(TruthMode::Full);
  bool force = false;
  int threads = 0;
  KnnParams knn;
  double p_h = OctoMapParams{}.p_h;
};

// The k-NN direct build with the scans' searches and rays on `threads` workers (0: all): the same map as one
// thread's KnnInverseSensorModel::buildMap (parallelBuildMap). In an arena of that many threads, as `sweep` runs,
// so that parallelBuildMap's batch (twice the arena's threads) follows --threads. liboctomap's build stays on one
// thread.
std::unique_ptr<octomap::OcTree> buildKnnMap(const PointCloudSet& scans, const KnnParams& k, int threads) {
  tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
  return arena.execute(
      [&] { return parallelBuildMap(KnnInverseSensorModel(k), scans, parallelKnnDistances(scans, k.k, k.s_c)); });
}

constexpr const char* kSettingsFormat = "occsweep-map-settings";

bool isOccsweepSettings(const std::filesystem::path& file) {
  if (!std::filesystem::is_regular_file(file)) return false;  // a FIFO would block the read below
  if (jsonOutput("", kSettingsFormat).is_own(file)) return true;
  try {  // written before the format field existed: occsweep's keys
    std::ifstream in(file);
    const auto j = nlohmann::json::parse(in);
    return j.is_object() && j.contains("method") && j.contains("parameters") && j.contains("dataset_hash");
  } catch (const std::exception&) {
    return false;
  }
}

// A .ot is occsweep's own when it is an OctoMap .ot with occsweep's settings beside it (a .ot from another tool has
// no .ot.json, and is refused even with --force).
ReplaceableOutput mapOutput() {
  return {"map (.ot with its .ot.json)", [](const std::filesystem::path& ot) {
            std::ifstream in(ot, std::ios::binary);
            std::string head(21, '\0');
            in.read(head.data(), std::streamsize(head.size()));
            return in && head == "# Octomap OcTree file" && isOccsweepSettings(ot.string() + ".json");
          }};
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

void addProbability(CLI::App& app, const std::string& flag, double& value, const std::string& help) {
  app.add_option(flag, value, help)->capture_default_str()->check(probability());
}

void addMapOptions(CLI::App& app, MapOptions& o) {
  KnnParams& k = o.knn;
  app.add_option("--dataset", o.dataset, "Data-set folder")->required();
  app.add_option("--out", o.out, "Output map, .ot (written with MAP.ot.json; .bt is refused)")->required();
  app.add_flag("--force", o.force, "Replace occsweep's own previous map and settings at --out (nothing else)");
  app.add_option("--method", o.method, "Mapping method")->check(CLI::IsMember({"octomap", "knn"}))->capture_default_str();
  addProbability(app, "--p-h", o.p_h, "OctoMap: probability of a hit");
  addProbability(app, "--p-m", k.p_m, "Miss probability (k-NN: rays to points within s_c)");
  addProbability(app, "--p-m-out", k.p_m_out, "k-NN: p'_m, miss for rays to points beyond s_c only");
  addProbability(app, "--p-u", k.p_u, "k-NN: upper bound of p(s) (Eq. 6)");
  addProbability(app, "--p-l", k.p_l, "k-NN: lower bound of p(s) (Eq. 6)");
  addProbability(app, "--p-max", k.p_max, "Upper clamping threshold");
  addProbability(app, "--p-min", k.p_min, "Lower clamping threshold");
  addProbability(app, "--p-t", k.p_t, "Occupancy threshold of the TP/FP/FN/TN summary (recorded in MAP.ot.json; the .ot keeps log-odds only)");
  app.add_option("--k", k.k, "k-NN: neighbours averaged")->capture_default_str()->check(integerAtLeast<int>(1));
  app.add_option("--s-c", k.s_c, "Maximum range s_c, metres")->capture_default_str()->check(numberAbove(0));
  app.add_option("--resolution", k.resolution, "Voxel edge, metres")->capture_default_str()->check(numberAbove(0));
  app.add_option("--variant", o.variant, "k-NN update: default (occupied wins) or literal (Algorithm 1 word for word)")
      ->check(CLI::IsMember(kUpdateVariantNames.list()))->capture_default_str();
  app.add_option("--stats", o.stats, "k-NN mu, sigma: batch (whole set, the paper's) or online (running)")
      ->check(CLI::IsMember(kStatsModeNames.list()))->capture_default_str();
  app.add_option("--truth", o.truth, "Truth of the TP/FP/FN/TN summary: full, or observable (only truth voxels a ray "
                                     "from a scan origin reaches within s_c first; docs/results-format.md)")
      ->check(CLI::IsMember(kTruthModeNames.list()))->capture_default_str();
  app.add_option("--threads", o.threads, "Worker threads of the k-NN build (0: all cores; the map is the same)")
      ->capture_default_str()->check(threadCount());
  addLimitOptions(app, {Limit::WindowVoxels, Limit::RegionVoxels, Limit::Points});
}

// Refuses broken parameters and outputs before reading anything. liboctomap writes .ot whatever the name; a .bt
// name would hold .ot bytes that octovis and readBinary misread.
void checkMapRequest(const MapOptions& o, const KnnParams& k, const OctoMapParams& om) {
  namespace fs = std::filesystem;
  if (fs::path(o.out).extension() == ".bt")
    throw std::invalid_argument("--out " + o.out + ": .bt keeps only occupied/free, not the log-odds the " +
                                "evaluation reads: write .ot (octovis opens it; octomap's convert_octree makes a .bt)");
  if (fs::path(o.out).extension() != ".ot")
    throw std::invalid_argument("--out " + o.out + ": must end in .ot (the map is written as OctoMap .ot, "
                                "log-odds kept)");
  if (o.method == "octomap") validate(om); else validate(k);
  requireCompanionName(o.out, ".json");
  checkOutputTarget(o.out, o.force, mapOutput());
  // occsweep's own settings without their map are what a kill between the two renames leaves (the .ot.json is
  // renamed first): a leftover of occsweep's, replaced like a stale temporary (docs/robustness.md).
  const bool orphan_settings = !fs::exists(fs::symlink_status(o.out)) && isOccsweepSettings(o.out + ".json");
  checkOutputTarget(o.out + ".json", o.force || orphan_settings, jsonOutput("map settings (.ot.json)", kSettingsFormat));
}

// The .ot format keeps resolution and log-odds only: the resolved settings go beside it, in MAP.ot.json.
nlohmann::json mapSettings(const MapOptions& o, const KnnParams& k, const OctoMapParams& om, const Dataset& d,
                           double seconds) {
  nlohmann::json params = {{"p_m", k.p_m}, {"p_max", k.p_max}, {"p_min", k.p_min}, {"p_t", k.p_t},
                           {"resolution", k.resolution}, {"s_c", k.s_c}};
  if (o.method == "octomap") {
    params["p_h"] = om.p_h;
  } else {
    params.update({{"p_m_out", k.p_m_out}, {"p_u", k.p_u}, {"p_l", k.p_l}, {"k", k.k}, {"variant", o.variant},
                   {"stats", o.stats}});
  }
  return {{"format", kSettingsFormat}, {"method", o.method}, {"dataset", o.dataset}, {"dataset_name", d.name},
          {"dataset_hash", datasetContentHash(o.dataset)}, {"parameters", params}, {"build_seconds", seconds}};
}

// The map and its settings, both written out and checked before either is renamed: a failed write (a full disk,
// `ulimit -f`) or a file put at either name meanwhile leaves neither.
void writeMapAndSettings(const octomap::OcTree& tree, const nlohmann::json& settings, const std::string& out) {
  OutputFile map_file(out);
  if (!tree.write(map_file.stream())) throw OutputError(out + ": liboctomap could not write the map");
  OutputFile settings_file(out + ".json");
  settings_file.stream() << settings.dump(1) << '\n';
  OutputFile::commitTogether({&map_file, &settings_file});  // neither when either fails or was taken meanwhile
}

int runMap(const MapOptions& o) {
  KnnParams k = o.knn;
  k.variant = parseUpdateVariant(o.variant);
  k.stats = parseStatsMode(o.stats);
  const OctoMapParams om{o.p_h, k.p_m, k.p_max, k.p_min, k.p_t, k.resolution, k.s_c};
  checkMapRequest(o, k, om);
  const Dataset d = readDataset(o.dataset);
  requireInKeyRange(d, o.dataset, k.resolution);
  warnWhenAllBeyondRange(d.scans, k.s_c);
  // The truth is built before the map: a region it cannot use (past its limit, no voxel) costs no build and leaves
  // no map.
  const bool has_truth = !d.truth.boxes.empty() || !d.truth.mesh.empty() || !d.truth.points.empty();
  std::optional<GroundTruth> gt;
  const TruthMode truth = parseTruthMode(o.truth);
  if (has_truth) gt = evaluatedTruth(truth, groundTruthOf(d, o.dataset, k.resolution), d.scans, k.s_c, o.dataset);
  const auto start = std::chrono::steady_clock::now();
  auto tree = o.method == "octomap" ? buildOctoMap(d.scans, om) : buildKnnMap(d.scans, k, o.threads);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  writeMapAndSettings(*tree, mapSettings(o, k, om, d, seconds), o.out);
  std::cout << "method " << o.method << ", " << d.scans.size() << " scans, " << pointCount(d.scans)
            << " points, built in " << seconds << " s\n"
            << "map " << o.out << ": " << tree->getNumLeafNodes() << " leaves (settings in " << o.out << ".json)\n";
  if (gt) {
    const ConfusionCounts c = classify(sampleRegion(*tree, *gt), k.p_t);
    std::cout << "at p_t " << k.p_t << (truth == TruthMode::Observable ? " (observable truth)" : "") << ": TP "
              << c.tp << " FP " << c.fp << " FN " << c.fn << " TN " << c.tn << "  TPR " << c.tpr() << " FDR "
              << c.fdr() << '\n';
  }
  return 0;
}

const RegisterCommand kMap{"map", "Build one map of a data set and write it as OctoMap .ot (octovis opens it)",
                           [](CLI::App& app) {
  addExample(app, "occsweep map --dataset ds --method knn --out knn.ot");
  auto o = std::make_shared<MapOptions>();
  addMapOptions(app, *o);
  return [o] { return runMap(*o); };
}};

}  // namespace
}  // namespace occsweep::cli
