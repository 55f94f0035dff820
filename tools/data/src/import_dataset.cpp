#include "occsweep/data/import_dataset.hpp"

#include <algorithm>
#include <limits>

#include "occsweep/core/limits.hpp"
#include "occsweep/core/voxel_filter.hpp"
#include "occsweep/io/data_error.hpp"

namespace occsweep {

Dataset importedDataset(std::string name, PointCloudSet scans, nlohmann::json source) {
  Dataset d;
  d.name = std::move(name);
  d.region = boundingBox(scans);
  d.scans = std::move(scans);
  source["truth"] = "none";
  d.source = std::move(source);
  return d;
}

void voxelFilterScans(Dataset& d, double leaf) {
  requireVoxelFilterLeaf(leaf, "--voxel-filter");
  for (Scan& scan : d.scans) scan.points = voxelFilter(scan.points, leaf);
  d.region = boundingBox(d.scans);
  d.source["voxel_filter_leaf"] = leaf;
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
