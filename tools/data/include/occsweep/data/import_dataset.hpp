// What an imported recording becomes: a data set without ground truth until `import truth` adds one.
#pragma once

#include <chrono>
#include <iostream>
#include <string>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "occsweep/eval/dataset.hpp"

namespace occsweep {

/// A data set of real scans without ground truth: empty truth sources and, as evaluation region, the bounding box
/// of the points and origins, so that readDataset accepts it unchanged and `map` prints no confusion counts
/// (docs/import.md). `source` records the reader and its settings; source.truth is set to "none".
[[nodiscard]] Dataset importedDataset(std::string name, PointCloudSet scans, nlohmann::json source);

/// `import depth|graph|cloud ... --voxel-filter LEAF` (docs/import.md): every scan replaced by the voxel filter
/// of core/voxel_filter.hpp at `leaf` (PCL VoxelGrid semantics), in the data set's own frame (after --shift, so
/// that its voxels are the map's at resolution `leaf`); the region becomes the filtered points' bounding box, and
/// source.voxel_filter_leaf records the leaf, as the stereo generator records its own. Throws
/// std::invalid_argument naming --voxel-filter for a leaf that is not a finite number above 0.
void voxelFilterScans(Dataset& dataset, double leaf);

/// "label i/n" on stderr. On a terminal one line rewritten in place, ended when the import ends (also by an error,
/// so that an error message starts on its own line); into a log file or pipe whole lines only, the first, the last
/// and one every 5 s, so that a log holds no carriage returns (docs/robustness.md).
class ProgressLine {
 public:
  explicit ProgressLine(std::string label)
      : label_(std::move(label)), terminal_(::isatty(STDERR_FILENO) != 0), last_(std::chrono::steady_clock::now()) {}
  ProgressLine(const ProgressLine&) = delete;
  ProgressLine& operator=(const ProgressLine&) = delete;
  ~ProgressLine() {
    if (shown_ && terminal_) std::cerr << '\n';
  }
  void show(std::size_t done, std::size_t total) {
    if (terminal_) {
      std::cerr << '\r' << label_ << ' ' << done << '/' << total << std::flush;
      shown_ = true;
      return;
    }
    const auto now = std::chrono::steady_clock::now();
    if (shown_ && done != total && now - last_ < std::chrono::seconds(5)) return;
    std::cerr << label_ << ' ' << done << '/' << total << '\n' << std::flush;
    shown_ = true;
    last_ = now;
  }

 private:
  std::string label_;
  bool terminal_, shown_ = false;
  std::chrono::steady_clock::time_point last_;
};

/// Throws DataError(file, where, ...) when a scan has no point: data sets refuse empty scans.
void requireNonEmpty(const Scan& scan, const std::string& file, const std::string& where);

/// Adds a scan's points to `total`; past limits().points (--max-points) throws DataError naming `file`, the one
/// whose points crossed the limit (the imported set is held in memory, then by every reader).
void countPoints(std::uint64_t& total, const Scan& scan, const std::string& file);

}  // namespace occsweep
