// occsweep import depth|graph|cloud|truth FILES... --out DIR: real recordings into the data-set format (issue 8).
#include <iostream>
#include <sstream>

#include "command_registry.hpp"
#include "limit_options.hpp"
#include "occsweep/core/limits.hpp"
#include "occsweep/core/mapping_params.hpp"
#include "occsweep/core/point_cloud_set.hpp"
#include "occsweep/data/import_cloud.hpp"
#include "occsweep/data/import_depth.hpp"
#include "occsweep/data/import_graph.hpp"
#include "occsweep/data/import_truth.hpp"

namespace occsweep::cli {
namespace {

namespace fs = std::filesystem;

struct ImportOptions {
  std::vector<std::string> files;
  std::string out, name, poses, pose_format = "quaternion", dataset;
  DepthImportConfig depth;
  std::vector<double> origin{0, 0, 0}, region;
  bool skip_empty = false;
};

constexpr const char* kPointsBox = "no truth: the bounding box of every point and origin";

PoseFormat poseFormat(const std::string& s) { return s == "matrix" ? PoseFormat::Matrix : PoseFormat::Quaternion; }

std::vector<fs::path> paths(const std::vector<std::string>& files) { return {files.begin(), files.end()}; }

// Which region the data set got and what it costs at the default resolution (issue 13: a region of 3.1e9
// voxels went unnoticed until a sweep was killed).
void printRegion(const AxisBox& r, const std::string& origin) {
  const double resolution = KnnParams{}.resolution;
  const std::uint64_t voxels = regionVoxelCount(r, resolution);
  std::cout << "region (" << origin << "): [" << r.min[0] << ", " << r.max[0] << "] x [" << r.min[1] << ", "
            << r.max[1] << "] x [" << r.min[2] << ", " << r.max[2] << "] m, " << voxels << " voxels at "
            << resolution << " m\n";
  if (voxels > limits().region_voxels)
    std::cout << "note: more than the limit of " << limits().region_voxels
              << " region voxels: map and sweep refuse it at this resolution (give --region, or "
                 "--max-region-voxels to them)\n";
}

int finish(Dataset d, const ImportOptions& o, const std::string& region_origin) {
  d.name = !o.name.empty() ? o.name : fs::path(o.out).filename().string();
  if (d.name.empty()) d.name = "imported";
  writeDataset(d, o.out);  // atomic: built beside the target, then renamed
  std::cout << "wrote " << o.out << ": " << d.scans.size() << " scans, " << pointCount(d.scans) << " points";
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
  sub->add_option("--pose-format", o.pose_format, "Pose file lines: quaternion (tx ty tz qx qy qz qw) or matrix (4x4)")
      ->check(CLI::IsMember({"quaternion", "matrix"}))->capture_default_str();
}

const RegisterCommand kImport{"import", "Import real recordings (depth images, OctoMap graphs, point clouds, truth)",
                              [](CLI::App& app) {
  auto o = std::make_shared<ImportOptions>();
  CLI::App* depth = app.add_subcommand("depth", "Depth images (16-bit PNG or PGM) with one pose each");
  CLI::App* graph = app.add_subcommand("graph", "An OctoMap scan graph (.graph)");
  CLI::App* cloud = app.add_subcommand("cloud", "Point clouds (PLY, PCD, x y z text), one scan each");
  CLI::App* truth = app.add_subcommand("truth", "Add ground truth (PLY mesh or cloud, PCD, JSON boxes) to a data set");
  for (CLI::App* sub : {depth, graph, cloud, truth}) {
    sub->add_option("files", o->files, "Input files, in scan order")->required();
    sub->add_option("--out", o->out, "Output data-set folder (written atomically)")->required();
    sub->add_option("--name", o->name, "Data-set name (default: the output folder's name)");
  }
  addLimitOptions(*depth, {Limit::ImagePixels, Limit::Points});
  for (CLI::App* sub : {graph, cloud, truth}) addLimitOptions(*sub, {Limit::Points});
  for (CLI::App* sub : {depth, graph, cloud})
    sub->add_flag("--skip-empty", o->skip_empty, "Drop scans without a valid point instead of refusing them");
  DepthImportConfig& c = o->depth;
  depth->add_option("--poses", o->poses, "Pose file, camera-to-world, one pose per image")->required();
  addPoseOptions(depth, *o);
  depth->add_option("--depth-scale", c.depth_scale, "Raw units per metre (1000 = mm; TUM/ICL-NUIM 5000)")->capture_default_str();
  depth->add_option("--fx", c.fx, "Focal length x, pixels")->required();
  depth->add_option("--fy", c.fy, "Focal length y, pixels (may be negative)")->required();
  depth->add_option("--cx", c.cx, "Principal point x, pixels")->required();
  depth->add_option("--cy", c.cy, "Principal point y, pixels")->required();
  depth->add_option("--max-depth", c.max_depth, "Drop depths >= this, metres (0 = keep all)")->capture_default_str();
  depth->add_option("--stride", c.stride, "Use every n-th pixel in u and v")->capture_default_str();
  cloud->add_option("--poses", o->poses, "Pose file, sensor-to-world, one pose per cloud (default: clouds in world frame)");
  addPoseOptions(cloud, *o);
  cloud->add_option("--origin", o->origin, "Sensor origin of every cloud when there is no pose file")->expected(3);
  truth->add_option("--dataset", o->dataset, "Data set to add the truth to")->required();
  truth->add_option("--region", o->region, "Evaluation region: minx miny minz maxx maxy maxz (default: the truth's bounding box grown by 0.5 m)")->expected(6);
  app.require_subcommand(1);
  return [=] {
    return runChosen({
        {depth, [o] {
           o->depth.pose_format = poseFormat(o->pose_format);
           o->depth.skip_empty = o->skip_empty;
           return finish(importDepthSequence(paths(o->files), o->poses, o->depth), *o, kPointsBox);
         }},
        {graph, [o] {
           if (o->files.size() != 1) throw std::invalid_argument("give exactly one .graph file");
           return finish(importScanGraph(o->files[0], o->skip_empty), *o, kPointsBox);
         }},
        {cloud, [o] {
           CloudImportConfig cc;
           if (!o->poses.empty()) cc.pose_file = fs::path(o->poses);
           cc.pose_format = poseFormat(o->pose_format);
           cc.origin = {o->origin[0], o->origin[1], o->origin[2]};
           cc.skip_empty = o->skip_empty;
           return finish(importClouds(paths(o->files), cc), *o, kPointsBox);
         }},
        {truth, [o] {
           Dataset d = readDataset(o->dataset);
           d.truth = {};
           for (const auto& f : o->files) {
             const TruthSources t = readTruth(f);
             d.truth.boxes.insert(d.truth.boxes.end(), t.boxes.begin(), t.boxes.end());
             d.truth.mesh.insert(d.truth.mesh.end(), t.mesh.begin(), t.mesh.end());
             d.truth.points.insert(d.truth.points.end(), t.points.begin(), t.points.end());
           }
           std::ostringstream region_origin_text;
           region_origin_text << "the truth's bounding box grown by " << kTruthRegionMargin << " m";
           std::string region_origin = region_origin_text.str();
           d.region = truthRegion(d.truth);
           if (!o->region.empty()) {
             d.region = {{o->region[0], o->region[1], o->region[2]}, {o->region[3], o->region[4], o->region[5]}};
             region_origin = "--region";
             for (int a = 0; a < 3; ++a)
               if (!(d.region.min[std::size_t(a)] <= d.region.max[std::size_t(a)]))
                 throw std::invalid_argument("--region: min must be <= max on every axis");
           }
           d.source["truth"] = o->files;
           if (o->name.empty()) o->name = d.name;
           return finish(std::move(d), *o, region_origin);
         }},
    });
  };
}};

}  // namespace
}  // namespace occsweep::cli
