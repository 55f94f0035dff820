// PCL's two outlier filters before OctoMap as registered methods (docs/methods.md, "sor-octomap", "ror-octomap"):
// each filter's per-point score as a feature, a gate on it for replay, and the filter then liboctomap when built.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "point_filters.hpp"
#include "occsweep/methods/octomap/octomap_method.hpp"

namespace occsweep {

/// Minus PCL StatisticalOutlierRemoval's mean distance to the k nearest points of the whole scan (higher: more
/// likely kept); the scan's summary holds PCL's mean and standard deviation of them.
class SorScoreFeature final : public ScanFeature {
 public:
  explicit SorScoreFeature(int k) : k_(k) {}
  FeatureIdentity identity() const override { return {"sor-score", {double(k_)}, ""}; }
  void computeScan(const Scan& scan, std::vector<double>& values, FeatureScanSummary& summary) const override;

 private:
  int k_;
};

/// How many other points of the scan PCL's RadiusOutlierRemoval finds within the radius (metres).
class RorNeighboursFeature final : public ScanFeature {
 public:
  explicit RorNeighboursFeature(double radius) : radius_(radius) {}
  FeatureIdentity identity() const override { return {"ror-neighbours", {radius_}, ""}; }
  void computeScan(const Scan& scan, std::vector<double>& values, FeatureScanSummary& summary) const override;

 private:
  double radius_;
};

/// PCL's StatisticalOutlierRemoval on each scan, then OctoMap (docs/methods.md, "sor-octomap").
class SorOctoMapMethod final : public OctoMapMethod {
 public:
  std::string name() const override { return "sor-octomap"; }
  std::string displayName() const override { return "SOR + OctoMap"; }
  std::string description() const override {
    return "PCL StatisticalOutlierRemoval (mean distance to k neighbours > mean + std_mul stddev) then OctoMap";
  }
  std::string reference() const override { return "Rusu et al., Robotics and Autonomous Systems 56(11), 2008; PCL 1.13"; }
  std::vector<MethodParameter> parameters() const override;
  std::vector<std::string> sharedByLanes() const override { return {"k"}; }
  MapRule rule(const MethodValues& v, const RuleContext& c) const override;
  std::unique_ptr<octomap::OcTree> buildMap(const PointCloudSet& set, const MethodValues& v,
                                            const MapContext& c) const override;
};

/// PCL's RadiusOutlierRemoval on each scan, then OctoMap (docs/methods.md, "ror-octomap").
class RorOctoMapMethod final : public OctoMapMethod {
 public:
  std::string name() const override { return "ror-octomap"; }
  std::string displayName() const override { return "ROR + OctoMap"; }
  std::string description() const override {
    return "PCL RadiusOutlierRemoval (fewer than min_neighbors points within radius) then OctoMap";
  }
  std::string reference() const override { return "PCL 1.13, pcl::RadiusOutlierRemoval (Rusu and Cousins, ICRA 2011)"; }
  std::vector<MethodParameter> parameters() const override;
  std::vector<std::string> sharedByLanes() const override { return {"radius"}; }
  MapRule rule(const MethodValues& v, const RuleContext& c) const override;
  std::unique_ptr<octomap::OcTree> buildMap(const PointCloudSet& set, const MethodValues& v,
                                            const MapContext& c) const override;
};

// ---------------------------------------------------------------------------------------------------------
namespace detail {

// Each scan's kept points, then liboctomap on what is left (the user's pipeline: filter, then insertPointCloud).
template <class Filter>
PointCloudSet filteredSet(const PointCloudSet& set, Filter&& keep) {
  PointCloudSet out(set.size());
  for (std::size_t t = 0; t < set.size(); ++t) {
    out[t].origin = set[t].origin;
    for (std::uint32_t i : keep(set[t].points)) out[t].points.push_back(set[t].points[i]);
  }
  return out;
}

}  // namespace detail

inline void SorScoreFeature::computeScan(const Scan& scan, std::vector<double>& values,
                                         FeatureScanSummary& summary) const {
  const SorDistances d = sorDistances(scan.points, k_);
  for (std::size_t i = 0; i < values.size(); ++i) values[i] = -double(d.mean_distance[i]);  // higher: more likely kept
  summary = {d.threshold_mean, d.threshold_stddev};
}

inline void RorNeighboursFeature::computeScan(const Scan& scan, std::vector<double>& values,
                                              FeatureScanSummary&) const {
  const std::vector<std::uint32_t> counts = rorNeighbourCounts(scan.points, radius_);
  for (std::size_t i = 0; i < values.size(); ++i) values[i] = double(counts[i]);
}

// --- sor-octomap ---

inline std::vector<MethodParameter> SorOctoMapMethod::parameters() const {
  std::vector<MethodParameter> p = {
      {"k", "k", "neighbours of each point averaged (PCL's mean_k)", 50, 1, 100000, false, false, true, "PCL setMeanK"},
      {"std_mul", "std_mul", "removed beyond mean + std_mul standard deviations (PCL's stddev_mult)", 1.0, 0, 1e6,
       false, false, false, "ours: grid values are not negative"}};
  for (MethodParameter& q : OctoMapMethod::parameters()) p.push_back(q);
  return p;
}

inline MapRule SorOctoMapMethod::rule(const MethodValues& v, const RuleContext& c) const {
  MapRule rule = OctoMapMethod::rule(v, c);
  const double std_mul = parameterValue(*this, v, "std_mul");
  // Kept when !(d > mean + std_mul * stddev) (PCL): the score is -d, so kept when -d >= -threshold. A NaN
  // threshold (one point: stddev divides by zero) removes nothing in PCL: -inf keeps every point here.
  rule.gate = PointGate{std::make_shared<SorScoreFeature>(int(parameterValue(*this, v, "k"))),
                        [std_mul](const FeatureScanSummary& s) {
                          const double t = sorThreshold(SorDistances{{}, s.mean, s.stddev}, std_mul);
                          return std::isnan(t) ? -std::numeric_limits<double>::infinity() : -t;
                        }};
  return rule;
}

inline std::unique_ptr<octomap::OcTree> SorOctoMapMethod::buildMap(const PointCloudSet& set, const MethodValues& v,
                                                                   const MapContext& c) const {
  const int k = int(parameterValue(*this, v, "k"));
  const double std_mul = parameterValue(*this, v, "std_mul");
  const auto keep = [&](const std::vector<octomap::point3d>& points) { return statisticalOutlierRemoval(points, k, std_mul); };
  return buildOctoMap(detail::filteredSet(set, keep), octomapParams(v, c));
}

// --- ror-octomap ---

inline std::vector<MethodParameter> RorOctoMapMethod::parameters() const {
  std::vector<MethodParameter> p = {
      {"radius", "r", "search radius in metres (PCL's search_radius)", 0.2, 0, 1e6, true, false, false, "PCL setRadiusSearch"},
      {"min_neighbors", "n_min", "removed with fewer neighbours within the radius (PCL's min_pts_radius)", 2, 0, 100000,
       false, false, true, "PCL setMinNeighborsInRadius"}};
  for (MethodParameter& q : OctoMapMethod::parameters()) p.push_back(q);
  return p;
}

inline MapRule RorOctoMapMethod::rule(const MethodValues& v, const RuleContext& c) const {
  MapRule rule = OctoMapMethod::rule(v, c);
  const double min_neighbors = parameterValue(*this, v, "min_neighbors");
  rule.gate = PointGate{std::make_shared<RorNeighboursFeature>(parameterValue(*this, v, "radius")),
                        [min_neighbors](const FeatureScanSummary&) { return min_neighbors; }};
  return rule;
}

inline std::unique_ptr<octomap::OcTree> RorOctoMapMethod::buildMap(const PointCloudSet& set, const MethodValues& v,
                                                                   const MapContext& c) const {
  const double radius = parameterValue(*this, v, "radius");
  const int min_neighbors = int(parameterValue(*this, v, "min_neighbors"));
  const auto keep = [&](const std::vector<octomap::point3d>& points) {
    return radiusOutlierRemoval(points, radius, min_neighbors);
  };
  return buildOctoMap(detail::filteredSet(set, keep), octomapParams(v, c));
}

}  // namespace occsweep
