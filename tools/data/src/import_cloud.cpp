#include <cctype>
#include <iostream>
#include <stdexcept>

#include "occsweep/eval/coordinates.hpp"
#include "occsweep/io/bounded_read.hpp"
#include "occsweep/data/import_cloud.hpp"
#include "occsweep/data/import_dataset.hpp"
#include "occsweep/data/byte_reader.hpp"

namespace occsweep {
namespace fs = std::filesystem;

namespace {

std::string lowerExtension(const fs::path& file) {
  std::string ext = file.extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

// What a coordinate that overflows float32 went through, for the error (docs/import.md, "Float overflow").
std::string afterWhat(const CloudImportConfig& c) {
  std::string what = c.pose_files.empty() ? "" : "after the pose of " + c.pose_files[0].string() +
                                                     (c.pose_files.size() > 1 ? " (or the others)" : "");
  if (c.shift != std::array<double, 3>{0, 0, 0}) what += std::string(what.empty() ? "after" : " and") + " --shift";
  return what;
}

}  // namespace

std::vector<octomap::point3d> decodeXyz(std::string_view bytes, const fs::path& file, const CloudPlacement& at) {
  TextLines lines(bytes, file);
  std::vector<std::string_view> tok;
  std::vector<octomap::point3d> pts;
  while (lines.nextData(tok)) {
    if (tok.size() < 3) lines.fail("has " + std::to_string(tok.size()) + " values, expected x y z");
    const double x = lines.number(tok[0], 0, "x"), y = lines.number(tok[1], 1, "y"), z = lines.number(tok[2], 2, "z");
    pts.push_back(at.place(x, y, z));
  }
  return pts;
}

std::vector<octomap::point3d> decodeCloud(std::string_view bytes, const fs::path& file, const CloudPlacement& at) {
  const std::string ext = lowerExtension(file);
  if (ext == ".ply") return decodePly(bytes, file, at).vertices;
  if (ext == ".pcd") return decodePcd(bytes, file, nullptr, at);
  return decodeXyz(bytes, file, at);
}

std::vector<octomap::point3d> readCloud(const fs::path& file, const CloudPlacement& at) {
  return decodeCloud(readFileBytes(file), file, at);
}

SensorView cloudView(const ConeView& cone, const RigidPose& pose) {
  if (const auto broken = brokenViewRule(cone))
    throw std::invalid_argument((broken->field == "axis" ? "--view-axis: " : "--view-half-angle: ") + broken->rule);
  if (cone.half_angle_deg >= 180) return SphereView{};
  const auto& r = pose.rotation;
  const auto& a = cone.axis;
  return ConeView{{r[0] * a[0] + r[1] * a[1] + r[2] * a[2], r[3] * a[0] + r[4] * a[1] + r[5] * a[2],
                   r[6] * a[0] + r[7] * a[1] + r[8] * a[2]},
                  cone.half_angle_deg};
}

Dataset importClouds(const std::vector<fs::path>& clouds, const CloudImportConfig& c) {
  if (clouds.empty()) throw std::invalid_argument("no point cloud given");
  if (c.view) (void)cloudView(*c.view, RigidPose{});  // its rules, before any file is read
  const bool posed = !c.pose_files.empty();
  const std::vector<RigidPose> poses =
      posed ? framePoses(c.pose_files, c.pose_format, clouds, "cloud", c.pose_selection, c.pose_convention)
            : std::vector<RigidPose>{};
  PointCloudSet scans;
  std::uint64_t total_points = 0;
  nlohmann::json files = nlohmann::json::array(), dropped = nlohmann::json::array();
  ProgressLine progress("point cloud");
  for (std::size_t i = 0; i < clouds.size(); ++i) {
    progress.show(i + 1, clouds.size());
    CloudPlacement at{posed ? poses[i] : RigidPose{}, c.shift};
    Scan scan;
    scan.points = readCloud(clouds[i], at);
    if (!posed) at.pose.translation = c.origin;  // points in the world frame, the sensor at --origin
    scan.origin = at.placeOrigin();
    files.push_back(clouds[i].filename().string());
    if (c.view) scan.view = cloudView(*c.view, posed ? poses[i] : RigidPose{});
    if (scan.points.empty() && c.skip_empty) {
      dropped.push_back(i);
      continue;
    }
    requireNonEmpty(scan, clouds[i].string(), "");
    requireFiniteScan(scan, clouds[i].string(), "", afterWhat(c));
    countPoints(total_points, scan, clouds[i].string());
    scans.push_back(std::move(scan));
  }
  if (scans.empty()) throw std::invalid_argument("every point cloud is empty");
  nlohmann::json source = {{"generator", "occsweep import cloud"}, {"clouds", files}};
  if (c.view) source["view"] = {{"axis", c.view->axis}, {"half_angle_deg", c.view->half_angle_deg}};
  if (!dropped.empty()) source["frames_dropped_empty"] = dropped;  // no part of its inputs (cmd_import.cpp)
  if (posed) {
    source["poses"] = poseFileNames(c.pose_files);
    recordPoseReading(source, c.pose_format, c.pose_selection, c.pose_convention);
  } else {
    source["origin"] = c.origin;
  }
  return importedDataset(clouds.front().stem().string(), std::move(scans), source);
}

}  // namespace occsweep
