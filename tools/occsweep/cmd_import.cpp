// occsweep import depth|graph|cloud|truth FILES... --out DIR: real recordings into the data-set format.
#include <array>
#include <cmath>
#include <cstdint>
#include <algorithm>
#include <iomanip>
#include <iostream>
#include <optional>
#include <sstream>
#include <tuple>

#include "command_registry.hpp"
#include "coverage_report.hpp"
#include "limit_options.hpp"
#include "option_checks.hpp"
#include "occsweep/core/limits.hpp"
#include "occsweep/core/map_settings.hpp"
#include "occsweep/core/point_cloud_set.hpp"
#include "occsweep/io/control_characters.hpp"
#include "occsweep/eval/coordinates.hpp"
#include "occsweep/eval/provenance.hpp"
#include "occsweep/data/import_dataset.hpp"
#include "occsweep/data/import_cloud.hpp"
#include "occsweep/data/import_depth.hpp"
#include "occsweep/data/import_graph.hpp"
#include "occsweep/data/import_truth.hpp"
#include "occsweep/io/output_target.hpp"

namespace occsweep::cli {
namespace {

namespace fs = std::filesystem;

struct ImportOptions {
  std::vector<std::string> files;
  std::string out, name, pose_format = "quaternion", pose_convention = "camera-to-world", dataset, intrinsics;
  PoseSelection pose_selection;  // --pose-start, --pose-step (chosen: either given)
  std::vector<std::string> poses;  ///< one file of every frame's pose, or one file a frame
  DepthImportConfig depth;
  std::vector<double> origin{0, 0, 0}, region, shift, view_axis;
  std::optional<double> view_half_angle;
  double voxel_filter = 0;  ///< the leaf of --voxel-filter; 0: off (the default)
  bool skip_empty = false, force = false;
};

std::vector<fs::path> paths(const std::vector<std::string>& files) { return {files.begin(), files.end()}; }

std::array<double, 3> shiftOf(const ImportOptions& o) {
  if (o.shift.empty()) return {0, 0, 0};
  for (double v : o.shift)
    if (!std::isfinite(v)) throw std::invalid_argument("--shift: must be 3 finite numbers");
  return {o.shift[0], o.shift[1], o.shift[2]};
}

// Far-away (georeferenced) coordinates: moved by --shift, or a warning with the shift to pass, since map and
// sweep refuse coordinates outside OctoMap's key range (docs/robustness.md, "Numbers that must not be wrong").
// `placed`: the reader already added the shift before rounding to float32 (import cloud, depth; docs/import.md).
void shiftOrWarn(Dataset& d, const ImportOptions& o, bool placed = false) {
  if (!o.shift.empty()) {
    if (placed) recordShift(d, shiftOf(o));
    else applyShift(d, shiftOf(o));
  }
  const KeyRange range = keyRange(0.1);
  const AxisBox b = boundingBox(d.scans);
  for (std::size_t a = 0; a < 3; ++a)
    if (!range.holds(b.min[a]) || !range.holds(b.max[a])) {
      const auto s = centringShift(d.scans, range);
      std::cerr << "occsweep import: warning: " << escapedControlCharacters(o.out) << ": the scans reach [" << b.min[a]
                << ", " << b.max[a] << "] m on axis " << "xyz"[a] << ", outside OctoMap's key range " << range.text()
                << ": map and sweep will refuse them at that resolution; import with --shift " << s[0] << ' ' << s[1]
                << ' ' << s[2] << " to centre them\n";
      return;
    }
}

// --voxel-filter, after the shift: the filter's voxels are then the map's at that resolution (docs/import.md).
void filterIfAsked(Dataset& d, const ImportOptions& o) {
  if (o.voxel_filter > 0) voxelFilterScans(d, o.voxel_filter);
}

constexpr const char* kPointsBox = "no truth: the bounding box of every point and origin";

// Which region the data set got and what it costs at the default resolution, so that a region of billions of
// voxels is seen at import, not when a sweep runs out of memory on it.
// Voxels whose centres lie in the region, wherever it lies: regionVoxelCount saturates outside OctoMap's key range,
// which is a different reason for map and sweep to refuse it than its size.
double extentVoxels(const AxisBox& r, double resolution) {
  double n = 1;
  for (std::size_t a = 0; a < 3; ++a)
    n *= std::max(0.0, std::floor(r.max[a] / resolution - 0.5) - std::ceil(r.min[a] / resolution - 0.5) + 1);
  return n;
}

void printRegion(const AxisBox& r, const std::string& origin) {
  const double resolution = MapSettings{}.resolution;
  const std::uint64_t voxels = regionVoxelCount(r, resolution);
  std::cout << "region (" << origin << "): [" << r.min[0] << ", " << r.max[0] << "] x [" << r.min[1] << ", "
            << r.max[1] << "] x [" << r.min[2] << ", " << r.max[2] << "] m, ";
  if (voxels == UINT64_MAX) {
    std::cout << std::fixed << std::setprecision(0) << extentVoxels(r, resolution) << std::defaultfloat
              << std::setprecision(6) << " voxels at " << resolution << " m, outside OctoMap's key range "
              << keyRange(resolution).text() << ": map and sweep refuse it there (import with --shift; "
                                                "docs/import.md)\n";
    return;
  }
  std::cout << voxels << " voxels at " << resolution << " m\n";
  if (voxels > limits().region_voxels)
    std::cout << "note: more than the limit of " << limits().region_voxels
              << " region voxels: map and sweep refuse it at this resolution (give --region, or "
                 "--max-region-voxels to them)\n";
}

// The input files whose scans the data set keeps, saying how many --skip-empty dropped: a dropped frame is no part
// of the recording, and a blank frame two recordings share must not join them (docs/dataset-format.md, "Provenance").
std::vector<fs::path> keptFrames(const Dataset& d, const ImportOptions& o) {
  std::vector<fs::path> kept = paths(o.files);
  const auto dropped = d.source.value("frames_dropped_empty", std::vector<std::size_t>{});  // ascending
  for (auto i = dropped.rbegin(); i != dropped.rend(); ++i) kept.erase(kept.begin() + std::ptrdiff_t(*i));
  if (!dropped.empty())
    std::cout << "--skip-empty: dropped " << dropped.size() << " of " << o.files.size()
              << " frames without a valid point (the first: " << escapedControlCharacters(o.files[dropped[0]])
              << ")\n";
  return kept;
}

// What the scans were made from, by content: compare counts data sets that share a recorded input, or the truth,
// as one scene (docs/dataset-format.md, "Provenance"; docs/statistics.md, "Verdicts").
void recordProvenance(Dataset& d, const ImportOptions& o) {
  nlohmann::json provenance = {{"inputs", fileContentHashes(keptFrames(d, o))}};
  if (!o.poses.empty()) provenance["poses"] = fileContentHashes(paths(o.poses));
  recordPoints(provenance, d.scans);  // before --shift and --voxel-filter: the recording as read
  d.source["provenance"] = std::move(provenance);
}

int finish(Dataset d, const ImportOptions& o, const std::string& region_origin) {
  d.name = !o.name.empty() ? o.name : outputTarget(o.out).filename().string();  // "ds/" is named ds
  if (d.name.empty()) d.name = "imported";
  writeDataset(d, o.out);  // atomic: built beside the target, then renamed
  std::cout << "wrote " << escapedControlCharacters(o.out) << ": data set \"" << escapedControlCharacters(d.name)
            << "\", " << d.scans.size() << " scans, " << pointCount(d.scans) << " points";
  if (d.truth.boxes.empty() && d.truth.mesh.empty() && d.truth.points.empty())
    std::cout << ", no ground truth (region = bounding box)";
  else
    std::cout << ", truth: " << d.truth.boxes.size() << " boxes, " << d.truth.mesh.size() << " triangles, "
              << d.truth.points.size() << " points";
  std::cout << '\n';
  printRegion(d.region, region_origin);
  return 0;
}

void addPoseOptions(CLI::App* sub, ImportOptions& o) {
  sub->add_option("--pose-format", o.pose_format,
                  "Pose file lines: quaternion (tx ty tz qx qy qz qw), matrix (4x4), tum (timestamp tx ty tz qx qy qz "
                  "qw) or kitti (12 numbers: 3x4 [R|t] row-major); docs/import.md")
      ->check(CLI::IsMember({"quaternion", "matrix", "tum", "kitti"}))->capture_default_str();
  CLI::Option* poses = sub->get_option("--poses");
  sub->add_option("--pose-convention", o.pose_convention,
                  "Which way the poses go: camera-to-world (p_world = R p + t; camera: the sensor) or world-to-camera "
                  "(each pose read as its inverse [R^T | -R^T t]); any --pose-format")
      ->check(CLI::IsMember({"camera-to-world", "world-to-camera"}))->capture_default_str()->needs(poses);
  sub->add_option("--pose-start", o.pose_selection.start,
                  "K: with one pose file of a whole sequence, the first frame takes pose K (counting from 0)")
      ->check(CLI::Range(std::size_t(0), std::size_t(1'000'000'000)))->needs(poses);
  sub->add_option("--pose-step", o.pose_selection.step,
                  "N: with one pose file of a whole sequence, frame i takes pose K + i N (10: every tenth)")
      ->check(CLI::Range(std::size_t(1), std::size_t(1'000'000)))->needs(poses);
  sub->add_flag("--pose-by-frame-number", o.pose_selection.by_frame_number,
                "With one pose file of a whole sequence, each frame takes the pose numbered by the one number in its "
                "file name, counting from 0 (Replica's depth000120.png: pose 120 of traj.txt)")
      ->needs(poses)->excludes("--pose-start")->excludes("--pose-step");
}

/// Either of --pose-start, --pose-step given (PoseSelection::chosen).
PoseSelection poseSelectionOf(const CLI::App& sub, const ImportOptions& o) {
  PoseSelection s = o.pose_selection;
  s.chosen = sub.count("--pose-start") + sub.count("--pose-step") > 0;
  return s;
}

/// The four kinds of input, each its own subcommand.
struct ImportCommands {
  CLI::App *depth, *graph, *cloud, *truth;
};

/// Options every import has; scan imports name the data set from --name, truth keeps the data set's name.
void addCommonOptions(const ImportCommands& subs, ImportOptions& o) {
  for (CLI::App* sub : {subs.depth, subs.graph, subs.cloud, subs.truth}) {
    CLI::Option* files = sub->add_option("files", o.files, "Input files, in scan order")->type_name(kPath);
    // depth and cloud check it themselves (requireFramesBeforePoses): a --poses before the frames takes them all
    if (sub == subs.graph || sub == subs.truth) files->required();
    sub->add_option("--out", o.out, "Output data-set folder (written atomically; a new one, or occsweep's own with "
                                    "--force)")
        ->type_name(kPath)->required();
    sub->add_flag("--force", o.force, "Replace occsweep's own previous data set at --out (nothing else)");
    if (sub != subs.truth)
      sub->add_option("--name", o.name, "Data-set name (default: the output folder's name)")->check(printableName());
  }
  subs.truth->add_option("--name", o.name, "Data-set name (default: the name of --dataset, kept)")
      ->check(printableName());
  addLimitOptions(*subs.depth, {Limit::ImagePixels, Limit::Points});
  for (CLI::App* sub : {subs.graph, subs.cloud}) addLimitOptions(*sub, {Limit::Points});
  addLimitOptions(*subs.truth, {Limit::Points, Limit::JsonBytes});  // --dataset's manifest is read whole
  for (CLI::App* sub : {subs.depth, subs.graph, subs.cloud}) {
    sub->add_flag("--skip-empty", o.skip_empty, "Drop scans without a valid point instead of refusing them");
    sub->add_option("--shift", o.shift, "X Y Z metres added to every point and origin after the poses (far-away, "
                                        "e.g. UTM, clouds into OctoMap's key range); recorded as source.shift")
        ->expected(3);
    sub->add_option("--voxel-filter", o.voxel_filter, "LEAF metres: per scan, PCL VoxelGrid's filter (one point per "
                    "voxel at its points' centroid), after --shift; recorded as source.voxel_filter_leaf (default: off)")
        ->check(voxelLeaf());
  }
}

void addDepthOptions(CLI::App& depth, ImportOptions& o) {
  DepthImportConfig& c = o.depth;
  depth.add_option("--poses", o.poses, "Pose file (--pose-convention): one for all images (one pose each, or a TUM "
                                      "trajectory matched by timestamp), or one per image in order; after the images")
      ->type_name(kPath)
      ->required();
  addPoseOptions(&depth, o);
  depth.add_option("--depth-scale", c.depth_scale, "Raw units per metre (1000 = mm; TUM/ICL-NUIM 5000)")->capture_default_str();
  CLI::Option* file = depth.add_option("--intrinsics", o.intrinsics, "Intrinsics file: a 3x3 camera matrix as text "
                                       "(3DMatch's camera-intrinsics.txt) or Replica's cam_params.json, whose scale "
                                       "(required without --depth-scale) is the depth scale unless --depth-scale; "
                                       "instead of --fx --fy --cx --cy")
                            ->type_name(kPath);
  for (const auto& [flag, value, help] : {std::tuple{"--fx", &c.fx, "Focal length x, pixels"},
                                          {"--fy", &c.fy, "Focal length y, pixels (may be negative)"},
                                          {"--cx", &c.cx, "Principal point x, pixels"},
                                          {"--cy", &c.cy, "Principal point y, pixels"}})
    depth.add_option(flag, *value, help)->excludes(file);
  depth.add_option("--max-depth", c.max_depth, "Drop depths >= this, metres (0 = keep all)")->capture_default_str();
  depth.add_option("--stride", c.stride, "Use every n-th pixel in u and v")->capture_default_str();
}

void addCloudOptions(CLI::App& cloud, ImportOptions& o) {
  cloud.add_option("--poses", o.poses, "Pose file (--pose-convention): one for all clouds, or one per cloud in order; "
                                      "after the clouds (default: clouds in world frame)")->type_name(kPath);
  addPoseOptions(&cloud, o);
  cloud.add_option("--origin", o.origin, "Sensor origin of every cloud when there is no pose file")->expected(3);
  cloud.add_option("--view-axis", o.view_axis, "X Y Z: the sensor's cone axis, in the sensor frame with --poses "
                                              "(each pose turns it), else in the world frame (docs/import.md)")
      ->expected(3);
  cloud.add_option("--view-half-angle", o.view_half_angle, "Degrees in (0, 180] around --view-axis that the sensor "
                                                           "sees; 180 (no axis needed): every direction");
}

// The cone of --view-axis and --view-half-angle, or none: then the data set records no view and observable truth
// looks in every direction from its origins, with a warning (docs/import.md, "Sensor views").
std::optional<ConeView> coneOfFlags(const ImportOptions& o) {
  if (!o.view_half_angle) {
    if (!o.view_axis.empty()) throw std::invalid_argument("--view-axis needs --view-half-angle (degrees)");
    return std::nullopt;
  }
  if (o.view_axis.empty() && *o.view_half_angle != 180) {
    std::ostringstream why;
    why << "--view-half-angle " << *o.view_half_angle << " needs --view-axis X Y Z (only 180, every direction, has "
        << "no axis)";
    throw std::invalid_argument(why.str());
  }
  ConeView cone{{0, 0, 1}, *o.view_half_angle};
  if (!o.view_axis.empty()) cone.axis = {o.view_axis[0], o.view_axis[1], o.view_axis[2]};
  return cone;
}

void addTruthOptions(CLI::App& truth, ImportOptions& o) {
  truth.add_option("--dataset", o.dataset, "Data set to add the truth to")->type_name(kPath)->required();
  truth.add_option("--region", o.region, "Evaluation region: minx miny minz maxx maxy maxz (default: the truth's bounding box grown by 0.5 m)")->expected(6);
}

ImportCommands addImportOptions(CLI::App& app, ImportOptions& o) {
  const ImportCommands subs{
      app.add_subcommand("depth", "Depth images (16-bit PNG or PGM) with one pose each"),
      app.add_subcommand("graph", "An OctoMap scan graph (.graph)"),
      app.add_subcommand("cloud", "Point clouds (PLY, PCD, x y z text), one scan each"),
      app.add_subcommand("truth", "Add ground truth (PLY mesh or cloud, PCD, JSON boxes) to a data set")};
  addCommonOptions(subs, o);
  const std::string real = "tests/data/real/";  // the repository's samples (tests/data/real/README.md)
  addExample(*subs.depth, "occsweep import depth " + real + "slambook_joinMap/depth/*.pgm --poses " + real +
                              "slambook_joinMap/pose.txt --fx 518 --fy 519 --cx 325.5 --cy 253.5 --max-depth 7 "
                              "--stride 8 --out room");
  addExample(*subs.graph, "occsweep import graph " + real + "octomap_share_data/spherical_scan.graph --out sphere");
  addExample(*subs.cloud, "occsweep import cloud " + real + "octomap_share_data/scan_first2000.xyz --out cloud");
  addExample(*subs.truth, "occsweep import truth tests/data/examples/boxes.json --dataset cloud --out cloud-truth");
  addDepthOptions(*subs.depth, o);
  addCloudOptions(*subs.cloud, o);
  addTruthOptions(*subs.truth, o);
  app.require_subcommand(1);
  return subs;
}

/// The median measured depth, and a warning when no depth camera would measure it: a wrong --depth-scale puts every
/// point 5 or 1000 times too far or too near, and the map then scores nothing (docs/import.md, "Depth scale").
void reportMedianDepth(const Dataset& d, double depth_scale) {
  const double median = d.source.value("median_depth", 0.0);
  std::cout << "median depth " << median << " m (raw value / --depth-scale " << depth_scale << ")\n";
  if (median < kPlausibleDepthMin || median > kPlausibleDepthMax)
    std::cerr << "warning: a median depth of " << median << " m is outside the " << kPlausibleDepthMin << "-"
              << kPlausibleDepthMax << " m depth cameras measure: is --depth-scale " << depth_scale
              << " right? (raw units per metre: 1000 for millimetres, 5000 for TUM and ICL-NUIM)\n";
}

/// --poses takes every file up to the next option, so `--poses P FRAME...` leaves no frame: said so, with the order.
void requireFramesBeforePoses(const ImportOptions& o, const std::string& frames) {
  if (!o.files.empty()) return;
  throw CLI::ValidationError("files", "no " + frames + " given" +
                                          (o.poses.size() > 1 ? ": --poses takes every file up to the next option, "
                                                                "so give the " + frames + " before --poses"
                                                              : ""));
}

int runImportDepth(const ImportOptions& o, const CLI::App& depth) {
  requireFramesBeforePoses(o, "depth images");
  DepthImportConfig c = o.depth;
  if (!o.intrinsics.empty()) c = withIntrinsicsFile(c, o.intrinsics, depth.count("--depth-scale") > 0);
  else if (depth.count("--fx") + depth.count("--fy") + depth.count("--cx") + depth.count("--cy") != 4)
    throw std::invalid_argument("the camera's intrinsics have no default: give --intrinsics FILE (3DMatch's "
                                "camera-intrinsics.txt, Replica's cam_params.json) or all of --fx --fy --cx --cy");
  c.pose_format = poseFormatNamed(o.pose_format);
  c.pose_selection = poseSelectionOf(depth, o);
  c.pose_convention = poseConventionNamed(o.pose_convention);
  c.skip_empty = o.skip_empty;
  c.shift = shiftOf(o);
  Dataset d = importDepthSequence(paths(o.files), paths(o.poses), c);
  reportMedianDepth(d, c.depth_scale);
  recordProvenance(d, o);
  shiftOrWarn(d, o, true);
  filterIfAsked(d, o);
  return finish(std::move(d), o, kPointsBox);
}

int runImportGraph(const ImportOptions& o) {
  if (o.files.size() != 1) throw std::invalid_argument("give exactly one .graph file");
  Dataset d = importScanGraph(o.files[0], o.skip_empty);
  recordProvenance(d, o);
  shiftOrWarn(d, o);
  filterIfAsked(d, o);
  return finish(std::move(d), o, kPointsBox);
}

int runImportCloud(const ImportOptions& o, const CLI::App& cloud) {
  requireFramesBeforePoses(o, "point clouds");
  CloudImportConfig cc;
  cc.pose_files = paths(o.poses);
  cc.pose_format = poseFormatNamed(o.pose_format);
  cc.pose_selection = poseSelectionOf(cloud, o);
  cc.pose_convention = poseConventionNamed(o.pose_convention);
  cc.origin = {o.origin[0], o.origin[1], o.origin[2]};
  cc.skip_empty = o.skip_empty;
  cc.view = coneOfFlags(o);
  cc.shift = shiftOf(o);
  Dataset d = importClouds(paths(o.files), cc);
  recordProvenance(d, o);
  if (o.poses.empty())  // clouds in the world frame: --origin is where the sensor was, the poses of the recording
    d.source["provenance"]["poses"] = nlohmann::json::array({contentHash(nlohmann::json(o.origin).dump())});
  shiftOrWarn(d, o, true);
  filterIfAsked(d, o);
  return finish(std::move(d), o, kPointsBox);
}

/// Every truth file, in the recording's frame like the scans before the shift, replaces the data set's truth.
TruthSources readTruthFiles(const std::vector<std::string>& files, const std::array<double, 3>& shift) {
  TruthSources truth;
  for (const auto& f : files) {
    TruthSources t = readTruth(f, shift);  // shifted in double, rounded to float once (docs/import.md)
    truth.boxes.insert(truth.boxes.end(), t.boxes.begin(), t.boxes.end());
    truth.mesh.insert(truth.mesh.end(), t.mesh.begin(), t.mesh.end());
    truth.points.insert(truth.points.end(), t.points.begin(), t.points.end());
  }
  return truth;
}

/// --region, in the recording's frame too; min <= max on every axis.
AxisBox regionGiven(const std::vector<double>& region, const std::array<double, 3>& s) {
  const AxisBox box{{region[0] + s[0], region[1] + s[1], region[2] + s[2]},
                    {region[3] + s[0], region[4] + s[1], region[5] + s[2]}};
  for (int a = 0; a < 3; ++a)
    if (!(box.min[std::size_t(a)] <= box.max[std::size_t(a)]))
      throw std::invalid_argument("--region: min must be <= max on every axis");
  return box;
}

// What the scans observe of the new truth, at the default resolution and s_c that sweep uses; none when map and
// sweep would refuse the region there (printRegion says so) or no truth voxel lies in it.
std::optional<TruthCoverage> importedCoverage(const Dataset& d) {
  const MapSettings defaults;
  const std::uint64_t voxels = regionVoxelCount(d.region, defaults.resolution);
  if (voxels == 0 || voxels > limits().region_voxels) return std::nullopt;
  TruthCoverage c = measureTruthCoverage(d.truth, d.region, defaults.resolution, d.scans, defaults.s_c);
  if (c.truth_voxels == 0) return std::nullopt;
  return c;
}

int runImportTruth(const ImportOptions& o) {
  Dataset d = readDataset(o.dataset);
  d.truth = readTruthFiles(o.files, recordedShift(d));
  std::ostringstream region_origin_text;
  region_origin_text << "the truth's bounding box grown by " << kTruthRegionMargin << " m";
  std::string region_origin = region_origin_text.str();
  d.region = truthRegion(d.truth);
  if (!o.region.empty()) {
    d.region = regionGiven(o.region, recordedShift(d));
    region_origin = "--region";
  }
  d.source["truth"] = o.files;
  recordTruthAndRegion(d.source["provenance"], d.truth, d.region);  // by value: one truth however it is written
  ImportOptions named = o;
  if (named.name.empty()) named.name = d.name;  // the data set keeps its name unless --name
  const std::optional<TruthCoverage> coverage = importedCoverage(d);
  const int written = finish(std::move(d), named, region_origin);
  if (coverage) reportCoverage(*coverage, TruthMode::Full, "occsweep import", o.out);
  return written;
}

int runImport(const ImportOptions& o, const ImportCommands& subs) {
  checkOutputTarget(o.out, o.force, datasetOutput());  // before any file is read
  return runChosen({
      {subs.depth, [&o, &subs] { return runImportDepth(o, *subs.depth); }},
      {subs.graph, [&o] { return runImportGraph(o); }},
      {subs.cloud, [&o, &subs] { return runImportCloud(o, *subs.cloud); }},
      {subs.truth, [&o] { return runImportTruth(o); }},
  });
}

const RegisterCommand kImport{"import", "Import real recordings (depth images, OctoMap graphs, point clouds, truth)",
                              [](CLI::App& app) {
  auto o = std::make_shared<ImportOptions>();
  const ImportCommands subs = addImportOptions(app, *o);
  return [o, subs] { return runImport(*o, subs); };
}};

}  // namespace
}  // namespace occsweep::cli
