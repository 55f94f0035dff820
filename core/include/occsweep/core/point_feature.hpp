// A per-point quantity a method declares (docs/methods.md, "Features"): what it is (its identity) and how it is
// computed for a whole point cloud set. The engines and the direct mappers compute each feature through this one
// interface and share it among maps by identity, so they see the same numbers and know no feature by name.
#pragma once

#include <any>
#include <compare>
#include <cstdint>
#include <limits>
#include <map>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

#include "point_cloud_set.hpp"
#include "scan_executor.hpp"

namespace occsweep {

/// What a feature is: two features of equal identity give equal values for every point cloud set.
struct FeatureIdentity {
  std::string name;               ///< the quantity, unique among features ("range")
  std::vector<double> arguments;  ///< every number its values depend on besides the points: its own and the
                                  ///< settings it reads (s_c)
  std::string mode;               ///< a setting it reads that is no number (a statistics mode), or empty
  friend auto operator<=>(const FeatureIdentity&, const FeatureIdentity&) = default;
  friend bool operator==(const FeatureIdentity&, const FeatureIdentity&) = default;
};

/// What a feature says about a whole scan (a filter's threshold may read it: a mean and a standard deviation).
struct FeatureScanSummary {
  double mean = 0.0, stddev = 0.0;
};

/// One feature of every point of a point cloud set.
struct SetFeature {
  std::vector<std::vector<double>> values;    ///< per scan, per point (NaN where the feature has none)
  std::vector<FeatureScanSummary> summaries;  ///< per scan
};

/// Recorded hits (scan_events.hpp): per hit its scan and its index among the scan's in-range points
/// (innerPoints(scan, s_c)), as the events name them.
struct HitPoints {
  const std::vector<std::uint32_t>& scan;
  const std::vector<std::uint32_t>& inner;
  double s_c = 0.0;
};

/// A per-point quantity of a method.
class PointFeature {
 public:
  virtual ~PointFeature() = default;
  [[nodiscard]] virtual FeatureIdentity identity() const = 0;
  /// The value of every point of every scan and each scan's summary; scans on `executor`, in any order, with the
  /// same result.
  [[nodiscard]] virtual SetFeature compute(const PointCloudSet& set, const ScanExecutor& executor) const = 0;
  /// The values at `hits` only, each equal to compute()'s at its point. By default compute() read at the hits; a
  /// feature whose per-point step is costly computes it at the hits alone (the replay engine asks for these).
  [[nodiscard]] virtual std::vector<double> valuesAtHits(const PointCloudSet& set, const HitPoints& hits,
                                                         const ScanExecutor& executor) const;
};

/// A feature whose values in a scan depend on that scan alone, computed scan by scan.
class ScanFeature : public PointFeature {
 public:
  /// One scan's values (sized to its points, NaN before the call) and summary.
  virtual void computeScan(const Scan& scan, std::vector<double>& values, FeatureScanSummary& summary) const = 0;
  [[nodiscard]] SetFeature compute(const PointCloudSet& set, const ScanExecutor& executor) const override;
};

/// What the maps of one sweep share, computed once for its point cloud set and kept by identity: a feature's values,
/// or a method's own intermediate (the direct engine holds one; docs/methods.md, "Features").
class FeatureCache {
 public:
  /// The value kept under `identity`, made by `make()` on the first request. Serially, under the lock: a parallel
  /// loop in `make` could take another map's task, which would wait for this lock.
  template <class T, class Make>
  const T& get(const FeatureIdentity& identity, Make&& make);

 private:
  std::mutex mutex_;
  std::map<FeatureIdentity, std::any> entries_;  // std::map: references stay valid as it grows
};

// ---------------------------------------------------------------------------------------------------------

inline std::vector<double> PointFeature::valuesAtHits(const PointCloudSet& set, const HitPoints& hits,
                                                      const ScanExecutor& executor) const {
  const SetFeature all = compute(set, executor);
  std::vector<std::vector<std::uint32_t>> inner(set.size());
  executor.run(set.size(), [&](std::size_t t) { inner[t] = innerPoints(set[t], hits.s_c); });
  std::vector<double> out(hits.scan.size());
  for (std::size_t h = 0; h < out.size(); ++h) {
    const std::uint32_t t = hits.scan[h];
    out[h] = all.values[t][inner[t][hits.inner[h]]];
  }
  return out;
}

inline SetFeature ScanFeature::compute(const PointCloudSet& set, const ScanExecutor& executor) const {
  SetFeature out;
  out.values.resize(set.size());
  out.summaries.assign(set.size(), {});
  executor.run(set.size(), [&](std::size_t t) {
    out.values[t].assign(set[t].points.size(), std::numeric_limits<double>::quiet_NaN());
    computeScan(set[t], out.values[t], out.summaries[t]);
  });
  return out;
}

template <class T, class Make>
const T& FeatureCache::get(const FeatureIdentity& identity, Make&& make) {
  const std::lock_guard lock(mutex_);
  auto it = entries_.find(identity);
  if (it == entries_.end()) it = entries_.emplace(identity, std::any(T(make()))).first;
  if (const T* value = std::any_cast<T>(&it->second)) return *value;
  throw std::logic_error("FeatureCache: '" + identity.name + "' is kept as another type");
}

}  // namespace occsweep
