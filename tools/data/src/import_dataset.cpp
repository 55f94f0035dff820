#include "occsweep/data/import_dataset.hpp"

#include <algorithm>
#include <limits>

#include "occsweep/core/limits.hpp"
#include "occsweep/data/data_error.hpp"

namespace occsweep {

AxisBox boundingBox(const PointCloudSet& scans) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  AxisBox box{{inf, inf, inf}, {-inf, -inf, -inf}};
  auto grow = [&box](const octomap::point3d& p) {
    for (int a = 0; a < 3; ++a) {
      box.min[std::size_t(a)] = std::min(box.min[std::size_t(a)], double(p(a)));
      box.max[std::size_t(a)] = std::max(box.max[std::size_t(a)], double(p(a)));
    }
  };
  for (const auto& s : scans) {
    grow(s.origin);
    for (const auto& p : s.points) grow(p);
  }
  return box;
}

Dataset importedDataset(std::string name, PointCloudSet scans, nlohmann::json source) {
  Dataset d;
  d.name = std::move(name);
  d.region = boundingBox(scans);
  d.scans = std::move(scans);
  source["truth"] = "none";
  d.source = std::move(source);
  return d;
}

void countPoints(std::uint64_t& total, const Scan& scan, const std::string& file) {
  total += scan.points.size();
  try {
    checkLimit("points of the scans so far", total, limits().points, "--max-points");
  } catch (const LimitError& e) {
    throw DataError(file, "", e.what());
  }
}

void requireNonEmpty(const Scan& scan, const std::string& file, const std::string& where) {
  if (scan.points.empty())
    throw DataError(file, where, "an empty scan (no valid point): data sets refuse empty scans");
}

}  // namespace occsweep
