// Layout (little-endian), from liboctomap 1.9 ScanGraph::readBinary: uint32 nNodes; per node: uint32 nPts,
// nPts x (int32 3, 3 doubles), pose = (int32 3, 3 doubles translation) + (int32 4, 4 doubles w x y z), uint32 id;
// then uint32 nEdges; per edge: uint32 first, uint32 second, a pose, double weight.
#include <cmath>
#include <string>
#include <unordered_set>

#include <octomap/math/Pose6D.h>

#include "occsweep/eval/coordinates.hpp"
#include "occsweep/io/bounded_read.hpp"
#include "occsweep/data/import_dataset.hpp"
#include "occsweep/data/import_graph.hpp"
#include "occsweep/data/import_pose.hpp"
#include "occsweep/data/byte_reader.hpp"

namespace occsweep {
namespace {

constexpr std::uint64_t kPointBytes = 4 + 3 * 8;
constexpr std::uint64_t kPoseBytes = (4 + 3 * 8) + (4 + 4 * 8);
constexpr std::uint64_t kNodeMinBytes = 4 + kPoseBytes + 4;
constexpr std::uint64_t kEdgeBytes = 4 + 4 + kPoseBytes + 8;

double finite(ByteReader& in, const std::string& what) {
  const double v = in.f64le(what);
  if (!std::isfinite(v)) in.fail(what, "NaN or infinite value");
  return v;
}

std::array<double, 3> vector3(ByteReader& in, const std::string& what) {
  if (in.i32le(what + " tag") != 3) in.fail(what, "element tag must be 3 (a 3-vector): not an OctoMap graph");
  return {finite(in, what), finite(in, what), finite(in, what)};
}

octomath::Pose6D pose(ByteReader& in, const std::string& what) {
  const auto t = vector3(in, what + " translation");
  if (in.i32le(what + " rotation tag") != 4) in.fail(what, "quaternion tag must be 4: not an OctoMap graph");
  double q[4];
  for (double& v : q) v = finite(in, what + " rotation");
  bool ok = false;
  (void)poseFromQuaternion(0, 0, 0, q[0], q[1], q[2], q[3], ok);
  if (!ok) in.fail(what, "quaternion is more than 1e-3 from unit norm: not a rotation");
  const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  return octomath::Pose6D(octomath::Vector3(float(t[0]), float(t[1]), float(t[2])),
                          octomath::Quaternion(float(q[0] / n), float(q[1] / n), float(q[2] / n), float(q[3] / n)));
}

}  // namespace

PointCloudSet decodeScanGraph(std::string_view bytes, const std::filesystem::path& file, bool skip_empty) {
  ByteReader in(bytes, file);
  const std::uint32_t nodes = in.u32le("node count");
  in.need(std::uint64_t(nodes) * kNodeMinBytes, "node count " + std::to_string(nodes));
  PointCloudSet scans;
  std::unordered_set<std::uint32_t> ids;  // edges name nodes by id (ScanGraph::getNodeByID), not by index
  for (std::uint32_t n = 0; n < nodes; ++n) {
    const std::string node = "node " + std::to_string(n);
    const std::uint32_t count = in.u32le(node + " point count");
    // Check the bytes before allocating: a header claiming 4e9 points fails here, not in the allocator.
    in.need(std::uint64_t(count) * kPointBytes + kPoseBytes + 4, node + " with " + std::to_string(count) + " points");
    std::vector<octomath::Vector3> local;
    local.reserve(count);
    for (std::uint32_t i = 0; i < count; ++i) {
      const auto p = vector3(in, node + " point " + std::to_string(i));
      local.emplace_back(float(p[0]), float(p[1]), float(p[2]));
    }
    const octomath::Pose6D node_pose = pose(in, node + " pose");
    ids.insert(in.u32le(node + " id"));
    Scan scan;
    scan.origin = node_pose.trans();
    scan.points.reserve(local.size());
    for (const auto& p : local) scan.points.push_back(node_pose.transform(p));
    if (scan.points.empty()) {
      if (skip_empty) continue;
      in.fail(node, "has no points: data sets refuse empty scans (use --skip-empty)");
    }
    requireFiniteScan(scan, file.string(), node, "after the node's pose");
    scans.push_back(std::move(scan));
  }
  const std::uint32_t edges = in.u32le("edge count");
  in.need(std::uint64_t(edges) * kEdgeBytes, "edge count " + std::to_string(edges));
  for (std::uint32_t e = 0; e < edges; ++e) {
    const std::string edge = "edge " + std::to_string(e);
    const auto first = in.u32le(edge + " first"), second = in.u32le(edge + " second");
    if (!ids.count(first) || !ids.count(second)) in.fail(edge, "refers to a node id that does not exist");
    (void)pose(in, edge + " pose");
    (void)finite(in, edge + " weight");
  }
  if (in.remaining() != 0) in.fail("end", std::to_string(in.remaining()) + " bytes after the last edge");
  if (scans.empty()) throw DataError(file, "", "holds no non-empty scan");
  return scans;
}

Dataset importScanGraph(const std::filesystem::path& file, bool skip_empty) {
  auto scans = decodeScanGraph(readFileBytes(file), file, skip_empty);
  return importedDataset(file.stem().string(), std::move(scans),
                         {{"generator", "occsweep import graph"}, {"graph", file.filename().string()}});
}

}  // namespace occsweep
