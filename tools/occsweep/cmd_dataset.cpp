// occsweep dataset generate: the paper's 20 data sets reproduced with rendered stereo and StereoSGBM.
#include <iostream>
#include <sstream>

#include "cmd_dataset.hpp"
#include "cmd_dataset_middlebury.hpp"
#include "command_registry.hpp"
#include "option_checks.hpp"

#ifdef OCCSWEEP_HAVE_STEREO
#include <tbb/global_control.h>

#include "occsweep/io/output_file.hpp"
#include "occsweep/stereo/generate.hpp"
#include "occsweep/stereo/ranking.hpp"
#include "occsweep/stereo/realism.hpp"
#include "occsweep/sweeps/grid.hpp"
#endif

namespace occsweep::cli {
namespace {

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

/// The realism and experiment options onto the configuration; presets resolved for the scale's keyframe count.
void applyRealism(const DatasetOptions& o, stereo::GenerateConfig& c) {
  using namespace stereo;
  c.presets = {o.realistic ? "orbslam2" : o.pose_error, o.realistic ? "mismatch" : o.exposure, o.realistic};
  c.drift.jitter_metres = o.jitter_m;
  c.drift.jitter_deg = o.jitter_deg;
  if (c.presets.pose_error == "orbslam2") c.drift = orbslam2PoseError(c.scale.keyframes);
  c.render.right = {o.right_gain, o.right_offset, o.right_gamma, o.right_vignetting};
  if (c.presets.exposure == "mismatch") c.render.right = exposureMismatchPreset();
  c.scene.far_clutter = o.far_clutter || o.realistic;
  c.scene.box_height = o.box_height;
  c.voxel_filter = !o.no_voxel_filter;
  c.render.noise_scale = o.noise_scale;
}

#endif

/// docs/datasets.md, "Realism and experiment options": each preset excludes its raw knobs, --realistic all of them.
void addRealismOptions(CLI::App& gen, DatasetOptions& o) {
  auto* pose = gen.add_option("--pose-error", o.pose_error, "Keyframe pose error preset: orbslam2 (ORB-SLAM2 stereo "
                              "accuracy, drift and jitter)")->check(CLI::IsMember({"orbslam2"}));
  auto* jitter = gen.add_option("--pose-jitter", o.jitter_m, "Pose jitter: position noise per keyframe, metres "
                                "(sigma per axis, not accumulating)")->capture_default_str()->check(numberIn(0, 1));
  auto* rot = gen.add_option("--rot-jitter", o.jitter_deg, "Pose jitter: rotation noise per keyframe, degrees "
                             "(sigma about each axis)")->capture_default_str()->check(numberIn(0, 10));
  auto* exposure = gen.add_option("--exposure", o.exposure, "Right camera exposure preset: mismatch (gain 1.06, "
                                  "offset 0.002, gamma 1.03, vignetting 0.1)")->check(CLI::IsMember({"mismatch"}));
  auto* gain = gen.add_option("--right-gain", o.right_gain, "Right camera: gain on linear intensity")
                   ->capture_default_str()->check(numberRule(0, 10, true));
  auto* offset = gen.add_option("--right-offset", o.right_offset, "Right camera: black level offset, linear")
                     ->capture_default_str()->check(numberIn(-0.5, 0.5));
  auto* gamma = gen.add_option("--right-gamma", o.right_gamma, "Right camera: gamma relative to the left's 2.2")
                    ->capture_default_str()->check(numberRule(0, 5, true));
  auto* vignetting = gen.add_option("--right-vignetting", o.right_vignetting, "Right camera: extra darkening at the "
                                    "corners, fraction")->capture_default_str()->check(numberIn(0, 1));
  gen.add_flag("--far-clutter", o.far_clutter, "Buildings and trees 15-60 m away and clouds in the images (not truth)");
  gen.add_option("--box-height", o.box_height, "Height of the boxes, metres (0.47: tops off the 0.1 m voxel grid)")
      ->capture_default_str()->check(numberRule(0, 1, true));
  gen.add_flag("--no-voxel-filter", o.no_voxel_filter, "Write the raw reprojected points (truth stays at 0.1 m)");
  gen.add_option("--noise-scale", o.noise_scale, "Multiplier of the renderer's read and shot noise (0: noiseless)")
      ->capture_default_str()->check(numberIn(0, 10));
  auto* realistic = gen.add_flag("--realistic", o.realistic, "All realism options at their presets: --pose-error "
                                 "orbslam2 --exposure mismatch --far-clutter");
  for (auto* raw : {jitter, rot, gen.get_option("--pose-drift"), gen.get_option("--yaw-drift")}) pose->excludes(raw);
  for (auto* raw : {gain, offset, gamma, vignetting}) exposure->excludes(raw);
  for (auto* any : {pose, jitter, rot, exposure, gain, offset, gamma, vignetting, gen.get_option("--pose-drift"),
                    gen.get_option("--yaw-drift")})
    realistic->excludes(any);
}

const RegisterCommand kDataset{"dataset", "Generate the paper's 20 stereo data sets (rendered pairs, StereoSGBM)",
                               [](CLI::App& app) {
  auto o = std::make_shared<DatasetOptions>();
  CLI::App* gen = app.add_subcommand("generate", "Render a data set, run StereoSGBM per point cloud parameter set, "
                                                 "write OUT/NAME/pcs-*/ and OUT/NAME/ranking.json");
  addExample(*gen, "occsweep dataset generate --name building-plain-I --scale ci --pcs 0,1 --out gen");
  gen->add_option("--name", o->name, "ENV-TEXTURE-LAYOUT: {building,parking}-{plain,voronoi}-{I,O,T,L,S}");
  gen->add_flag("--all", o->all, "All 20 data sets (also writes OUT/summary.json)");
  gen->add_option("--out", o->out, "Output folder")->type_name(kPath)->required();
  gen->add_option("--scale", o->scale, "ci (320x180, 24 keyframes, 3 sets), small (640x360, 48, 9), paper (1280x720, 144, 1600)")
      ->check(CLI::IsMember({"ci", "small", "paper"}))->capture_default_str();
  gen->add_option("--sgbm", o->sgbm, "One custom point cloud set: blockSize=5,uniquenessRatio=10,speckleWindowSize=100,"
                                     "speckleRange=2,disp12MaxDiff=1 (omitted keys keep these values)");
  gen->add_option("--pcs", o->pcs, "Point cloud parameter ids, comma-separated (default: the scale's even subset)");
  gen->add_option("--pcs-grid", o->grid, "Point cloud parameter grid, name or file")->capture_default_str();
  gen->add_option("--seed", o->seed, "Seed of sensor noise and pose drift")->capture_default_str();
  gen->add_option("--pose-drift", o->drift_m, "SLAM-like drift: position random walk, metres per keyframe (sigma)")
      ->capture_default_str()->check(numberAtLeast(0));
  gen->add_option("--yaw-drift", o->drift_yaw, "SLAM-like drift: yaw random walk, degrees per keyframe (sigma)")
      ->capture_default_str()->check(numberAtLeast(0));
  addRealismOptions(*gen, *o);
  gen->add_flag("--no-preview", o->no_preview, "Do not write OUT/NAME/preview/*.png");
  gen->add_option("--threads", o->threads, "Worker threads (0: all cores)")->capture_default_str()->check(threadCount());
  gen->add_flag("--quiet", o->quiet, "No progress on stderr");
  gen->add_flag("--force", o->force, "Replace occsweep's own earlier output at the data sets' names (sets, ranking, "
                                     "timing, previews, summary; a user's file never)");
  const auto middlebury = addDatasetMiddlebury(app);  // `dataset middlebury`: cmd_dataset_middlebury.cpp
  return [o, gen, middlebury]() -> int {
    if (middlebury.first->parsed()) return middlebury.second();
    if (!gen->parsed()) throw CLI::CallForHelp();
    generateDatasets(*o);
    return 0;
  };
}};

}  // namespace

#ifdef OCCSWEEP_HAVE_STEREO
namespace {
ReplaceableOutput summaryOutput() { return jsonOutput("data-set summary", "occsweep-dataset-summary"); }
}  // namespace

void generateDatasets(const DatasetOptions& o) {
  if (o.all == !o.name.empty()) throw std::invalid_argument("give either --name ENV-TEXTURE-LAYOUT or --all");
  if (!o.sgbm.empty() && !o.pcs.empty()) throw std::invalid_argument("--sgbm and --pcs exclude each other");
  using namespace stereo;
  GenerateConfig c;
  c.scale = scaleConfig(o.scale);
  c.seed = o.seed;
  c.drift.metres_per_keyframe = o.drift_m;
  c.drift.yaw_deg_per_keyframe = o.drift_yaw;
  c.preview = !o.no_preview;
  c.progress = !o.quiet;
  c.force = o.force;
  applyRealism(o, c);
  const PointCloudGrid grid = loadPointCloudGrid(resolveGridPath(o.grid));
  if (!o.sgbm.empty()) c.custom = parseSgbmParams(o.sgbm);
  if (!o.pcs.empty()) c.pcs_ids = parseIds(o.pcs, grid.size());
  const std::vector<DatasetName> names = o.all ? allDatasetNames() : std::vector{parseDatasetName(o.name)};
  const std::filesystem::path summary_file = std::filesystem::path(o.out) / "summary.json";
  if (o.all) checkOutputTarget(summary_file, o.force, summaryOutput());  // before hours of work
  std::unique_ptr<tbb::global_control> limit;
  if (o.threads > 0) limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, o.threads);
  nlohmann::json summary = nlohmann::json::array();
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (!o.quiet) std::cerr << "data set " << i + 1 << "/" << names.size() << ": " << names[i].str() << " at scale " << o.scale << '\n';
    const DatasetSummary s = generateDataset(names[i], c, grid, o.out);
    const auto& m = s.medianRanked();
    std::cout << s.name << ": " << s.sets.size() << " point cloud sets; median-ranked " << m.folder << ": " << m.points
              << " points, valid on targets " << m.target_valid_fraction << ", naive TPR " << m.naive.tpr() << " FDR "
              << m.naive.fdr() << "; render " << s.render_seconds << " s\n";
    summary.push_back(summaryRow(s));
  }
  if (!o.all) return;
  checkOutputTarget(summary_file, true, summaryOutput());  // again: a user's file put there meanwhile stays
  writeJsonAtomically({{"format", "occsweep-dataset-summary"}, {"datasets", summary}}, summary_file);
}
#else
void generateDatasets(const DatasetOptions&) {
  throw std::runtime_error("dataset generate: this build has no stereo tools (configure with -DOCCSWEEP_STEREO=ON "
                           "and OpenCV's calib3d and imgproc)");
}
#endif

}  // namespace occsweep::cli
