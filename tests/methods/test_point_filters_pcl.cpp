// core/point_filters.hpp against PCL 1.13 itself: pcl::StatisticalOutlierRemoval<PointXYZ> and
// pcl::RadiusOutlierRemoval<PointXYZ>, Debian's libpcl-filters1.13 as the sor-octomap / ror-octomap baselines
// would have run them, on the seeded clouds of point_filter_cases.hpp; and core/voxel_filter.hpp against
// pcl::VoxelGrid<PointXYZ>, the filter of the paper's Section 4.2. Built only where PCL is installed
// (tests/core/CMakeLists.txt). PCL exposes only the kept (and removed) indices, not its distances or threshold:
// those are checked through the kept sets at thresholds placed exactly on each cloud's mean distances.
#include <catch2/catch.hpp>

#include <map>
#include <optional>

#include <pcl/console/print.h>
#include <pcl/filters/radius_outlier_removal.h>
#include <pcl/filters/statistical_outlier_removal.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include "methods/point_filter_cases.hpp"
#include "occsweep/methods/outlier_filters/point_filters.hpp"
#include "occsweep/core/voxel_filter.hpp"

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

TEST_CASE("k past the cloud's size (PCL caps it) and radii past the whole cloud keep exactly what PCL keeps") {
  // docs/methods.md, "Neighbour searches": the searches that stopped growing with k and the radius.
  QuietPcl quiet;
  for (std::uint64_t seed = 1; seed <= test::kFilterSeeds; seed += 2) {
    const auto c = test::filterCase(seed);
    const int n = int(c.points.size());
    INFO("seed " << seed << " (" << c.kind << ", " << n << " points)");
    const auto cloud = pclCloud(c.points);
    for (int mean_k : {129, n - 1, n, 100000})
      for (double std_mul : {-0.5, 0.0, 1.0}) {
        if (mean_k < 1) continue;
        INFO("mean_k " << mean_k << " std_mul " << std_mul);
        REQUIRE(statisticalOutlierRemoval(c.points, mean_k, std_mul) == pclSor(cloud, mean_k, std_mul));
      }
    for (double radius : {c.radii.back() * 8, 20.0, 1e6})
      for (int min_pts : {0, 2, n - 1, n}) {
        if (min_pts < 0) continue;
        INFO("radius " << radius << " min_neighbors " << min_pts);
        REQUIRE(radiusOutlierRemoval(c.points, radius, min_pts) == pclRor(cloud, radius, min_pts));
      }
  }
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

// ---------------------------------------------------------------------------------------------------------
// The voxel filter against pcl::VoxelGrid. PCL computes a point's voxel in float, floor(x * (1.0f / leaf))
// (voxel_grid.hpp:341-343), ours in double, floor(x / leaf): within a few float ulps of a voxel face the two may
// pick neighbouring voxels, a difference of rounding that core/voxel_filter.hpp documents and the last case below
// pins. So the random clouds keep every point where both computations give the same voxel (a hundredth of a voxel
// or more from any face), and the comparison is of the semantics: the same voxels in the same order, and centroids
// equal up to float rounding (PCL sums in float in its sort's order, we in double).

namespace {

struct VoxelCase {
  std::vector<octomap::point3d> points;
  double leaf = 0.1;
};

// PCL's voxel index of one coordinate, as voxel_grid.hpp:261 and :341 compute it (the offset min_b_ aside).
std::int64_t pclIndex(float x, double leaf) {
  const float inverse = 1.0f / float(leaf);  // setLeafSize: inverse_leaf_size_ = 1 / leaf_size_ in float
  const float product = x * inverse;
  return std::int64_t(std::floor(product));
}

// A point at least a hundredth of a voxel from every face, after rounding to float, where PCL's float index and
// ours agree (checked, not assumed).
bool awayFromFaces(const octomap::point3d& p, double leaf) {
  for (unsigned a = 0; a < 3; ++a) {
    const double scaled = double(p(a)) / leaf, fraction = scaled - std::floor(scaled);
    if (fraction < 0.01 || fraction > 0.99 || pclIndex(p(a), leaf) != std::int64_t(std::floor(scaled))) return false;
  }
  return true;
}

// Clusters of points in few voxels (up to thousands per voxel) or spread thinly, around an origin up to 60 m out on
// either side, at leaves exact in binary (0.25, 1) and not (0.05, 0.1, 0.37).
VoxelCase voxelCase(std::uint64_t seed) {
  SplitMix64 rng(seed * 7919);
  const double leaves[] = {0.05, 0.1, 0.25, 0.37, 1.0};
  VoxelCase c;
  c.leaf = leaves[rng.below(5)];
  const double base[3] = {rng.uniform() * 120 - 60, rng.uniform() * 120 - 60, rng.uniform() * 40 - 20};
  const std::uint64_t span = 1 + rng.below(rng.below(2) ? 4 : 40);  // voxels per axis
  const std::size_t n = 1 + rng.below(4000);
  while (c.points.size() < n) {
    octomap::point3d p;
    for (unsigned a = 0; a < 3; ++a) {
      const double voxel = std::floor(base[a] / c.leaf) + double(rng.below(span));
      p(a) = float((voxel + 0.005 + 0.99 * rng.uniform()) * c.leaf);
    }
    if (awayFromFaces(p, c.leaf)) c.points.push_back(p);
  }
  return c;
}

pcl::PointCloud<pcl::PointXYZ> pclVoxelGrid(const std::vector<octomap::point3d>& pts, double leaf) {
  pcl::VoxelGrid<pcl::PointXYZ> grid;
  grid.setInputCloud(pclCloud(pts));
  grid.setLeafSize(float(leaf), float(leaf), float(leaf));
  pcl::PointCloud<pcl::PointXYZ> out;
  grid.filter(out);
  return out;
}

// Per voxel: its points and the largest |coordinate| among them, per axis.
struct VoxelContent {
  std::size_t count = 0;
  double largest[3] = {0, 0, 0};
};

}  // namespace

TEST_CASE("voxelFilter gives PCL VoxelGrid's voxels in its order, centroids equal up to float rounding") {
  QuietPcl quiet;
  std::size_t voxels = 0, heavy = 0, differing = 0;
  for (std::uint64_t seed = 1; seed <= 300; ++seed) {
    const VoxelCase c = voxelCase(seed);
    INFO("seed " << seed << " (" << c.points.size() << " points, leaf " << c.leaf << ")");
    std::map<VoxelFilterKey, VoxelContent> content;
    for (const auto& p : c.points) {
      VoxelContent& v = content[voxelFilterKey(Eigen::Vector3d(p.x(), p.y(), p.z()), c.leaf)];
      v.count += 1;
      for (unsigned a = 0; a < 3; ++a) v.largest[a] = std::max(v.largest[a], std::abs(double(p(a))));
    }
    const auto ours = voxelFilter(c.points, c.leaf);
    const auto theirs = pclVoxelGrid(c.points, c.leaf);
    REQUIRE(ours.size() == theirs.size());
    REQUIRE(ours.size() == content.size());
    auto v = content.begin();
    for (std::size_t i = 0; i < ours.size(); ++i, ++v) {
      // Float summation of n terms (PCL) errs by at most (n - 1) u sum |x| <= (n - 1) u n max|x|, so the mean by
      // (n - 1) u max|x|; the division and our one rounding add u max|x| each: (n + 1) u max|x|, u = 2^-24.
      const double u = 0x1p-24, bound_terms = double(v->second.count + 1) * u;
      const float pcl_point[3] = {theirs[i].x, theirs[i].y, theirs[i].z};
      for (unsigned a = 0; a < 3; ++a) {
        INFO("voxel " << i << " axis " << a << " of " << v->second.count << " points");
        CHECK(std::abs(double(ours[i](a)) - double(pcl_point[a])) <= bound_terms * v->second.largest[a]);
        differing += ours[i](a) != pcl_point[a];
      }
      heavy += v->second.count >= 100;
    }
    voxels += ours.size();
  }
  // The clouds must exercise the filter: many voxels, heavily filled ones, and centroids where float and double
  // summation round differently (else the tolerance would be untested).
  CHECK(voxels > 50000);
  CHECK(heavy > 100);
  CHECK(differing > 100);
}

TEST_CASE("voxelFilter and PCL VoxelGrid put a point on a voxel face into the voxel above it, with an exact leaf") {
  QuietPcl quiet;
  // 0.25 and these coordinates are exact in float and double: both floors see the face x = 0.25 exactly, and the
  // point on it joins the one above (0.375), not the one below (0.125). Centroids are exact too.
  const std::vector<octomap::point3d> pts = {{0.25f, 0.125f, 0.125f}, {0.375f, 0.125f, 0.125f}, {0.125f, 0.125f, 0.125f}};
  const auto ours = voxelFilter(pts, 0.25);
  const auto theirs = pclVoxelGrid(pts, 0.25);
  REQUIRE(ours.size() == 2);
  REQUIRE(theirs.size() == 2);
  CHECK(ours[0] == octomap::point3d(0.125f, 0.125f, 0.125f));
  CHECK(ours[1] == octomap::point3d(0.3125f, 0.125f, 0.125f));
  for (std::size_t i = 0; i < 2; ++i) CHECK(ours[i] == octomap::point3d(theirs[i].x, theirs[i].y, theirs[i].z));
}

TEST_CASE("Near a face, PCL's float voxel index can differ from ours (the documented difference)") {
  QuietPcl quiet;
  // Search floats next to the faces of leaf 0.1 for one that PCL's floor(x * 10.0f) and our floor(x / 0.1) put into
  // different voxels; with a second point well inside our voxel of it, PCL merges the two and we do not (or the
  // reverse), which is what core/voxel_filter.hpp says.
  std::optional<float> found;
  for (int k = 1; k < 2000 && !found; ++k)
    for (float x = std::nextafter(float(k * 0.1), 0.0f), i = 0; i < 4; ++i, x = std::nextafter(x, 1e9f))
      if (pclIndex(x, 0.1) != std::int64_t(std::floor(double(x) / 0.1))) found = x;
  REQUIRE(found);
  const float x = *found;
  const std::int64_t ours_index = std::int64_t(std::floor(double(x) / 0.1));
  const float inside = float((double(ours_index) + 0.5) * 0.1);  // the middle of our voxel of x
  const std::vector<octomap::point3d> pts = {{x, 0.05f, 0.05f}, {inside, 0.05f, 0.05f}};
  INFO("x = " << x << ": ours in voxel " << ours_index << ", PCL's " << pclIndex(x, 0.1));
  CHECK(voxelFilter(pts, 0.1).size() == 1);
  CHECK(pclVoxelGrid(pts, 0.1).size() == 2);
}
