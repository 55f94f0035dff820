// The real sample recordings read through the import readers, each against an independent oracle (docs/import.md).
#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>
#include <sstream>

#include <octomap/OcTree.h>
#include <octomap/ScanGraph.h>

#include "occsweep/io/bounded_read.hpp"
#include "occsweep/data/import_cloud.hpp"
#include "occsweep/data/import_depth.hpp"
#include "occsweep/data/import_graph.hpp"
#include "test_paths.hpp"

using namespace occsweep;
namespace fs = std::filesystem;

namespace {
const fs::path kReal = occsweep::test::sourceTree() / "tests" / "data" / "real";
}

TEST_CASE("spherical_scan.graph: 1 node, 10,201 points, equal to liboctomap's own reader") {
  const fs::path file = kReal / "octomap_share_data" / "spherical_scan.graph";
  const PointCloudSet scans = decodeScanGraph(readFileBytes(file), file);
  REQUIRE(scans.size() == 1);
  REQUIRE(scans[0].points.size() == 10201);
  octomap::ScanGraph graph;  // oracle: OctoMap's ScanGraph::readBinary, poses applied as graph2tree does
  REQUIRE(graph.readBinary(file.string()));
  REQUIRE(graph.size() == 1);
  const octomap::ScanNode* node = *graph.begin();
  REQUIRE(node->scan->size() == 10201);
  CHECK(scans[0].origin == node->pose.trans());
  std::size_t differing = 0;
  for (std::size_t i = 0; i < node->scan->size(); ++i)
    if (!(scans[0].points[i] == node->pose.transform((*node->scan)[i]))) ++differing;
  CHECK(differing == 0);
}

TEST_CASE("slambook joinMap PGM frames: the book's own OctoMap is reproduced from our import") {
  const fs::path dir = kReal / "slambook_joinMap";
  const DepthImage first = readDepthImage(dir / "depth" / "1.pgm");
  CHECK(first.width == 640);
  CHECK(first.height == 480);
  // The book's settings (slambook ch5 joinMap, ch13 octomap_mapping): mm depth, 7 m cut, every pixel.
  DepthImportConfig c;
  c.fx = 518, c.fy = 519, c.cx = 325.5, c.cy = 253.5, c.depth_scale = 1000, c.max_depth = 7.0;
  std::vector<fs::path> images;
  for (int i = 1; i <= 5; ++i) images.push_back(dir / "depth" / (std::to_string(i) + ".pgm"));
  const Dataset d = importDepthSequence(images, {dir / "pose.txt"}, c);
  REQUIRE(d.scans.size() == 5);
  // Oracle: the book inserted each frame with OcTree's defaults at 0.05 m and saved octomap_ref.bt.
  octomap::OcTree ours(0.05);
  for (const auto& s : d.scans) {
    octomap::Pointcloud cloud;
    for (const auto& p : s.points) cloud.push_back(p);
    ours.insertPointCloud(cloud, s.origin);
  }
  ours.updateInnerOccupancy();
  octomap::OcTree ref((dir / "octomap_ref.bt").string());
  // Leaves are compared by looking each one up in the other tree: the .bt stores a binary (max-likelihood) tree
  // that prunes differently, so leaf counts alone differ.
  auto occupiedIn = [](const octomap::OcTree& from, const octomap::OcTree& in, std::size_t& occupied) {
    std::size_t agree = 0;
    occupied = 0;
    for (auto it = from.begin_leafs(); it != from.end_leafs(); ++it) {
      if (!from.isNodeOccupied(*it)) continue;
      ++occupied;
      const auto* n = in.search(it.getKey());
      agree += n && in.isNodeOccupied(n);
    }
    return agree;
  };
  std::size_t ref_occupied = 0, our_occupied = 0;
  const std::size_t ref_in_ours = occupiedIn(ref, ours, ref_occupied);
  const std::size_t ours_in_ref = occupiedIn(ours, ref, our_occupied);
  INFO("reference occupied leaves " << ref_occupied << " (" << ref_in_ours << " occupied in ours), ours "
                                    << our_occupied << " (" << ours_in_ref << " occupied in the reference)");
  REQUIRE(ref_occupied > 1000);
  CHECK(double(ref_in_ours) / double(ref_occupied) > 0.999);
  CHECK(double(ours_in_ref) / double(our_occupied) > 0.999);
}

TEST_CASE("ICL-NUIM 16-bit PNG frames: libpng decode, plausible depths, poses applied") {
  const fs::path dir = kReal / "slambook2_iclnuim_dense_RGBD";
  const DepthImage img = readDepthImage(dir / "depth" / "1.png");
  REQUIRE(img.width == 640);
  REQUIRE(img.height == 480);
  std::size_t valid = 0;
  double max_m = 0;
  for (auto v : img.values) valid += v != 0, max_m = std::max(max_m, v / 5000.0);
  CHECK(valid > img.values.size() / 2);  // a rendered scene: almost every pixel has a depth
  CHECK(max_m < 13.0);                   // 65535 / 5000: any larger would be a decoding error
  DepthImportConfig c;
  c.fx = 481.2, c.fy = -480, c.cx = 319.5, c.cy = 239.5, c.depth_scale = 5000, c.stride = 2;
  const Dataset d = importDepthSequence({dir / "depth" / "1.png", dir / "depth" / "2.png"}, {dir / "pose_1-2.txt"}, c);
  REQUIRE(d.scans.size() == 2);
  // Camera frame z is the depth: every point's distance to its camera is at least its depth and the origin is
  // the pose's translation.
  const auto poses = readPoses(dir / "pose_1-2.txt", PoseFormat::Quaternion);
  CHECK(d.scans[1].origin == poses[1].origin());
  for (const auto& p : d.scans[0].points) CHECK((p - d.scans[0].origin).norm() < 13.0f * 1.8f);
}

TEST_CASE("OctoMap's laser scan as x y z text: equal to a stream parse") {
  const fs::path file = kReal / "octomap_share_data" / "scan_first2000.xyz";
  const auto pts = readCloud(file);
  REQUIRE(pts.size() == 2000);
  std::ifstream in(file);
  float x, y, z;
  std::size_t i = 0, differing = 0;
  while (in >> x >> y >> z) differing += !(pts[i++] == octomap::point3d(x, y, z));
  CHECK(i == 2000);
  CHECK(differing == 0);
}
