// occsweep dataset generate: the paper's 20 data sets reproduced with rendered stereo and StereoSGBM (issue 4).
#include <iostream>
#include <sstream>

#include "cmd_dataset_middlebury.hpp"
#include "command_registry.hpp"
#include "option_checks.hpp"

#ifdef OCCSWEEP_HAVE_STEREO
#include <tbb/global_control.h>

#include "occsweep/stereo/generate.hpp"
#include "occsweep/stereo/ranking.hpp"
#include "occsweep/sweeps/grid.hpp"
#endif

namespace occsweep::cli {
namespace {

struct DatasetOptions {
  std::string name, out, scale = "ci", sgbm, pcs, grid = "pointcloud";
  bool all = false, no_preview = false;
  std::uint64_t seed = 1;
  double drift_m = 0, drift_yaw = 0;
  int threads = 0;
};

#ifdef OCCSWEEP_HAVE_STEREO
std::vector<std::uint64_t> parseIds(const std::string& text, std::uint64_t size) {
  std::vector<std::uint64_t> ids;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    std::size_t used = 0;
    unsigned long long v = 0;
    try {
      v = std::stoull(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != item.size() || item[0] == '-')
      throw std::invalid_argument("--pcs '" + item + "': not a point cloud parameter id");
    if (v >= size) throw std::invalid_argument("--pcs " + item + ": ids run from 0 to " + std::to_string(size - 1));
    ids.push_back(v);
  }
  if (ids.empty()) throw std::invalid_argument("--pcs: give at least one id");
  return ids;
}

int runGenerate(const DatasetOptions& o) {
  if (o.all == !o.name.empty()) throw std::invalid_argument("give either --name ENV-TEXTURE-LAYOUT or --all");
  if (!o.sgbm.empty() && !o.pcs.empty()) throw std::invalid_argument("--sgbm and --pcs exclude each other");
  using namespace stereo;
  GenerateConfig c;
  c.scale = scaleConfig(o.scale);
  c.seed = o.seed;
  c.drift.metres_per_keyframe = o.drift_m;
  c.drift.yaw_deg_per_keyframe = o.drift_yaw;
  c.preview = !o.no_preview;
  const PointCloudGrid grid = loadPointCloudGrid(resolveGridPath(o.grid));
  if (!o.sgbm.empty()) c.custom = parseSgbmParams(o.sgbm);
  if (!o.pcs.empty()) c.pcs_ids = parseIds(o.pcs, grid.size());
  const std::vector<DatasetName> names = o.all ? allDatasetNames() : std::vector{parseDatasetName(o.name)};
  std::unique_ptr<tbb::global_control> limit;
  if (o.threads > 0) limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, o.threads);
  nlohmann::json summary = nlohmann::json::array();
  for (std::size_t i = 0; i < names.size(); ++i) {
    std::cerr << "data set " << i + 1 << "/" << names.size() << ": " << names[i].str() << " at scale " << o.scale << '\n';
    const DatasetSummary s = generateDataset(names[i], c, grid, o.out);
    const auto& m = s.medianRanked();
    std::cout << s.name << ": " << s.sets.size() << " point cloud sets; median-ranked " << m.folder << ": " << m.points
              << " points, valid on targets " << m.target_valid_fraction << ", naive TPR " << m.naive.tpr() << " FDR "
              << m.naive.fdr() << "; render " << s.render_seconds << " s\n";
    summary.push_back(summaryRow(s));
  }
  if (o.all) writeJsonAtomically(summary, std::filesystem::path(o.out) / "summary.json");
  return 0;
}
#endif

const RegisterCommand kDataset{"dataset", "Generate the paper's 20 stereo data sets (rendered pairs, StereoSGBM)",
                               [](CLI::App& app) {
  auto o = std::make_shared<DatasetOptions>();
  CLI::App* gen = app.add_subcommand("generate", "Render a data set, run StereoSGBM per point cloud parameter set, "
                                                 "write OUT/NAME/pcs-*/ and OUT/NAME/ranking.json");
  gen->add_option("--name", o->name, "ENV-TEXTURE-LAYOUT: {building,parking}-{plain,voronoi}-{I,O,T,L,S}");
  gen->add_flag("--all", o->all, "All 20 data sets (also writes OUT/summary.json)");
  gen->add_option("--out", o->out, "Output folder")->required();
  gen->add_option("--scale", o->scale, "ci (320x180, 24 keyframes, 3 sets), small (640x360, 48, 9), paper (1280x720, 144, 1600)")
      ->check(CLI::IsMember({"ci", "small", "paper"}))->capture_default_str();
  gen->add_option("--sgbm", o->sgbm, "One custom point cloud set: blockSize=5,uniquenessRatio=10,speckleWindowSize=100,"
                                     "speckleRange=2,disp12MaxDiff=1 (omitted keys keep these values)");
  gen->add_option("--pcs", o->pcs, "Point cloud parameter ids, comma-separated (default: the scale's even subset)");
  gen->add_option("--grid", o->grid, "Point cloud parameter grid, name or file")->capture_default_str();
  gen->add_option("--seed", o->seed, "Seed of sensor noise and pose drift")->capture_default_str();
  gen->add_option("--pose-drift", o->drift_m, "SLAM-like drift: position random walk, metres per keyframe (sigma)")
      ->capture_default_str()->check(numberAtLeast(0));
  gen->add_option("--yaw-drift", o->drift_yaw, "SLAM-like drift: yaw random walk, degrees per keyframe (sigma)")
      ->capture_default_str()->check(numberAtLeast(0));
  gen->add_flag("--no-preview", o->no_preview, "Do not write OUT/NAME/preview/*.png");
  gen->add_option("--threads", o->threads, "Worker threads (0: all cores)")->capture_default_str()->check(integerAtLeast<int>(0));
  const auto middlebury = addDatasetMiddlebury(app);  // `dataset middlebury`: cmd_dataset_middlebury.cpp
  return [o, gen, middlebury]() -> int {
    if (middlebury.first->parsed()) return middlebury.second();
    if (!gen->parsed()) throw CLI::CallForHelp();
#ifdef OCCSWEEP_HAVE_STEREO
    return runGenerate(*o);
#else
    std::cerr << "occsweep dataset generate: this build has no stereo tools (configure with -DOCCSWEEP_STEREO=ON "
                 "and OpenCV's calib3d and imgproc)\n";
    return 2;
#endif
  };
}};

}  // namespace
}  // namespace occsweep::cli
