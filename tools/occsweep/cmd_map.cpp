// occsweep map: one map of a data set with OctoMap or the k-NN model, written as OctoMap's .ot.
#include <chrono>
#include <filesystem>
#include <iostream>
#include <optional>
#include <unistd.h>

#include "command_registry.hpp"
#include "limit_options.hpp"
#include "occsweep/core/knn_inverse_sensor_model.hpp"
#include "occsweep/core/octomap_baseline.hpp"
#include "occsweep/data/dataset.hpp"
#include "occsweep/eval/confusion.hpp"
#include "occsweep/sweeps/results.hpp"

namespace occsweep::cli {
namespace {

struct MapOptions {
  std::string dataset, out, method = "knn", variant = "default", stats = "batch";
  KnnParams knn;
  double p_h = OctoMapParams{}.p_h;
};

void addProbability(CLI::App& app, const std::string& flag, double& value, const std::string& help) {
  app.add_option(flag, value, help)->capture_default_str()->check(CLI::Range(0.0, 1.0));
}

const RegisterCommand kMap{"map", "Build one map of a data set and write it as OctoMap .ot (octovis opens it)",
                           [](CLI::App& app) {
  auto o = std::make_shared<MapOptions>();
  KnnParams& k = o->knn;
  app.add_option("--dataset", o->dataset, "Data-set folder")->required();
  app.add_option("--out", o->out, "Output map, .ot")->required();
  app.add_option("--method", o->method, "Mapping method")->check(CLI::IsMember({"octomap", "knn"}))->capture_default_str();
  addProbability(app, "--p-h", o->p_h, "OctoMap: probability of a hit");
  addProbability(app, "--p-m", k.p_m, "Miss probability (k-NN: rays to points within s_c)");
  addProbability(app, "--p-m-out", k.p_m_out, "k-NN: p'_m, miss for rays to points beyond s_c only");
  addProbability(app, "--p-u", k.p_u, "k-NN: upper bound of p(s) (Eq. 6)");
  addProbability(app, "--p-l", k.p_l, "k-NN: lower bound of p(s) (Eq. 6)");
  addProbability(app, "--p-max", k.p_max, "Upper clamping threshold");
  addProbability(app, "--p-min", k.p_min, "Lower clamping threshold");
  addProbability(app, "--p-t", k.p_t, "Occupancy threshold (stored in the .ot, used for the summary)");
  app.add_option("--k", k.k, "k-NN: neighbours averaged")->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--s-c", k.s_c, "Maximum range s_c, metres")->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--resolution", k.resolution, "Voxel edge, metres")->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--variant", o->variant, "k-NN update: default (occupied wins) or literal (Algorithm 1 word for word)")
      ->check(CLI::IsMember({"default", "literal"}))->capture_default_str();
  app.add_option("--stats", o->stats, "k-NN mu, sigma: batch (whole set, the paper's) or online (running)")
      ->check(CLI::IsMember({"batch", "online"}))->capture_default_str();
  addLimitOptions(app, {Limit::WindowVoxels, Limit::RegionVoxels, Limit::Points});
  return [o] {
    KnnParams k = o->knn;
    k.variant = o->variant == "literal" ? UpdateVariant::Literal : UpdateVariant::Default;
    k.stats = o->stats == "online" ? StatsMode::Online : StatsMode::Batch;
    const OctoMapParams om{o->p_h, k.p_m, k.p_max, k.p_min, k.p_t, k.resolution, k.s_c};
    // Refuse broken parameters before reading anything.
    if (o->method == "octomap") validate(om); else validate(k);
    const Dataset d = readDataset(o->dataset);
    const bool has_truth = !d.truth.boxes.empty() || !d.truth.mesh.empty() || !d.truth.points.empty();
    // Checked before the map is built, so a region past its limit costs no build and leaves no map.
    std::optional<GroundTruth> gt;
    if (has_truth) gt = groundTruthOf(d, o->dataset, k.resolution);
    const auto start = std::chrono::steady_clock::now();
    auto tree = o->method == "octomap" ? buildOctoMap(d.scans, om) : KnnInverseSensorModel(k).buildMap(d.scans);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    namespace fs = std::filesystem;
    const fs::path out = o->out, tmp = o->out + ".tmp-" + std::to_string(::getpid());
    if (out.has_parent_path()) fs::create_directories(out.parent_path());
    if (!tree->write(tmp.string())) throw std::runtime_error(o->out + ": cannot write the map");
    fs::rename(tmp, out);
    // The .ot format keeps resolution and log-odds only: the resolved settings go beside it.
    nlohmann::json params = {{"p_m", k.p_m}, {"p_max", k.p_max}, {"p_min", k.p_min}, {"p_t", k.p_t},
                             {"resolution", k.resolution}, {"s_c", k.s_c}};
    if (o->method == "octomap") {
      params["p_h"] = om.p_h;
    } else {
      params.update({{"p_m_out", k.p_m_out}, {"p_u", k.p_u}, {"p_l", k.p_l}, {"k", k.k}, {"variant", o->variant},
                     {"stats", o->stats}});
    }
    writeJsonAtomically({{"method", o->method}, {"dataset", o->dataset}, {"dataset_name", d.name},
                         {"dataset_hash", datasetContentHash(o->dataset)}, {"parameters", params},
                         {"build_seconds", seconds}},
                        o->out + ".json");
    std::cout << "method " << o->method << ", " << d.scans.size() << " scans, " << pointCount(d.scans)
              << " points, built in " << seconds << " s\n"
              << "map " << o->out << ": " << tree->getNumLeafNodes() << " leaves (settings in " << o->out << ".json)\n";
    if (gt) {
      const ConfusionCounts c = classify(sampleRegion(*tree, *gt), k.p_t);
      std::cout << "at p_t " << k.p_t << ": TP " << c.tp << " FP " << c.fp << " FN " << c.fn << " TN " << c.tn
                << "  TPR " << c.tpr() << " FDR " << c.fdr() << '\n';
    }
    return 0;
  };
}};

}  // namespace
}  // namespace occsweep::cli
