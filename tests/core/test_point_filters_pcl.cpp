// core/point_filters.hpp against PCL 1.13 itself: pcl::StatisticalOutlierRemoval<PointXYZ> and
// pcl::RadiusOutlierRemoval<PointXYZ>, Debian's libpcl-filters1.13 as the sor-octomap / ror-octomap baselines
// would have run them, on the seeded clouds of point_filter_cases.hpp. Built only where PCL is installed
// (tests/core/CMakeLists.txt). PCL exposes only the kept (and removed) indices, not its distances or threshold:
// those are checked through the kept sets at thresholds placed exactly on each cloud's mean distances.
#include <catch2/catch.hpp>

#include <pcl/console/print.h>
#include <pcl/filters/radius_outlier_removal.h>
#include <pcl/filters/statistical_outlier_removal.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include "core/point_filter_cases.hpp"
#include "occsweep/core/point_filters.hpp"

using namespace occsweep;

namespace {

pcl::PointCloud<pcl::PointXYZ>::Ptr pclCloud(const std::vector<octomap::point3d>& pts) {
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
  for (const auto& p : pts) cloud->push_back(pcl::PointXYZ(p.x(), p.y(), p.z()));  // width n, height 1, dense
  return cloud;
}

std::vector<std::uint32_t> asUnsigned(const pcl::Indices& indices) {
  return std::vector<std::uint32_t>(indices.begin(), indices.end());
}

std::vector<std::uint32_t> pclSor(const pcl::PointCloud<pcl::PointXYZ>::Ptr& cloud, int mean_k, double std_mul) {
  pcl::StatisticalOutlierRemoval<pcl::PointXYZ> sor;
  sor.setInputCloud(cloud);
  sor.setMeanK(mean_k);
  sor.setStddevMulThresh(std_mul);
  pcl::Indices kept;
  sor.filter(kept);
  return asUnsigned(kept);
}

std::vector<std::uint32_t> pclRor(const pcl::PointCloud<pcl::PointXYZ>::Ptr& cloud, double radius, int min_pts) {
  pcl::RadiusOutlierRemoval<pcl::PointXYZ> ror;
  ror.setInputCloud(cloud);
  ror.setRadiusSearch(radius);
  ror.setMinNeighborsInRadius(min_pts);
  pcl::Indices kept;
  ror.filter(kept);
  return asUnsigned(kept);
}

/// std_mul values that put our threshold exactly on (or one step beside) some points' mean distances, where a
/// distance off by one float ulp, or a comparison of the wrong strictness, changes the kept set.
std::vector<double> criticalStdMuls(const SorDistances& d) {
  std::vector<double> out;
  if (!(d.threshold_stddev > 0)) return out;
  for (std::size_t i = 0; i < d.mean_distance.size(); i += 1 + d.mean_distance.size() / 8) {
    const double m = (double(d.mean_distance[i]) - d.threshold_mean) / d.threshold_stddev;
    out.insert(out.end(), {m, std::nextafter(m, -1e300), std::nextafter(m, 1e300)});
  }
  return out;
}

struct QuietPcl {  // the empty cloud makes KdTreeFLANN print an error, expected here
  QuietPcl() { pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS); }
};

}  // namespace

TEST_CASE("statisticalOutlierRemoval keeps exactly what PCL's StatisticalOutlierRemoval keeps") {
  QuietPcl quiet;
  std::size_t comparisons = 0, removals = 0;
  for (std::uint64_t seed = 1; seed <= test::kFilterSeeds; ++seed) {
    const auto c = test::filterCase(seed);
    INFO("seed " << seed << " (" << c.kind << ", " << c.points.size() << " points, mean_k " << c.mean_k << ")");
    const auto cloud = pclCloud(c.points);
    std::vector<double> std_muls = test::kStdMuls;
    const auto critical = criticalStdMuls(sorDistances(c.points, c.mean_k));
    std_muls.insert(std_muls.end(), critical.begin(), critical.end());
    for (double std_mul : std_muls) {
      INFO("std_mul " << std_mul);
      const auto ours = statisticalOutlierRemoval(c.points, c.mean_k, std_mul);
      REQUIRE(ours == pclSor(cloud, c.mean_k, std_mul));
      ++comparisons;
      removals += c.points.size() - ours.size();
    }
  }
  // The clouds must exercise the filter: thousands of removals, not a suite where everything is kept.
  CHECK(comparisons > 2000);
  CHECK(removals > 10000);
}

TEST_CASE("radiusOutlierRemoval keeps exactly what PCL's RadiusOutlierRemoval keeps, at the lattice spacing too") {
  QuietPcl quiet;
  std::size_t removals = 0;
  for (std::uint64_t seed = 1; seed <= test::kFilterSeeds; ++seed) {
    const auto c = test::filterCase(seed);
    INFO("seed " << seed << " (" << c.kind << ", " << c.points.size() << " points)");
    const auto cloud = pclCloud(c.points);
    std::vector<double> radii = c.radii;
    radii.push_back(0.0);  // PCL's "No radius defined" branch
    for (double radius : radii)
      for (int min_pts : test::kMinNeighbours) {
        INFO("radius " << radius << " min_neighbors " << min_pts);
        const auto ours = radiusOutlierRemoval(c.points, radius, min_pts);
        REQUIRE(ours == pclRor(cloud, radius, min_pts));
        removals += c.points.size() - ours.size();
      }
  }
  CHECK(removals > 10000);
}

TEST_CASE("PCL's ROR on a lattice: a neighbour exactly at the radius counts (1.0 is exact in float and double)") {
  QuietPcl quiet;
  const std::vector<octomap::point3d> pts = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {4, 0, 0}};
  const auto cloud = pclCloud(pts);
  CHECK(pclRor(cloud, 1.0, 2) == std::vector<std::uint32_t>{1});
  CHECK(pclRor(cloud, 1.0, 1) == std::vector<std::uint32_t>{0, 1, 2});
  CHECK(radiusOutlierRemoval(pts, 1.0, 2) == std::vector<std::uint32_t>{1});
  CHECK(radiusOutlierRemoval(pts, 1.0, 1) == std::vector<std::uint32_t>{0, 1, 2});
}

TEST_CASE("PCL's other ROR path, taken only for clouds marked not dense, does not count a neighbour at the radius") {
  // radius_outlier_removal.hpp:132-151 calls radiusSearch with float(radius * radius) (kdtree_flann.hpp:400) and
  // FLANN's RadiusResultSet keeps dist < radius (flann/util/result_set.h:477): strict. Our filters reproduce the
  // dense path (a cloud of finite points); this pins the difference a caller of PCL with is_dense false would see.
  QuietPcl quiet;
  const std::vector<octomap::point3d> pts = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {4, 0, 0}};
  auto cloud = pclCloud(pts);
  cloud->is_dense = false;
  CHECK(pclRor(cloud, 1.0, 1).empty());
  CHECK(pclRor(cloud, 1.5, 2) == std::vector<std::uint32_t>{1});
}
