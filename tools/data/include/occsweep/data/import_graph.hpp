// OctoMap scan graphs (.graph, ScanGraph::writeBinary): the nodes' scans, moved to the world by their poses.
#pragma once

#include <filesystem>
#include <string_view>

#include "occsweep/eval/dataset.hpp"

namespace occsweep {

/// One scan a node, in file order: points transformed by the node pose exactly as liboctomap does
/// (octomath::Pose6D::transform, float arithmetic), origin = the pose's translation. Edges are checked (node
/// indices in range, finite) and ignored. DataError for a truncated file, counts the bytes cannot hold, wrong
/// element tags, NaN or infinite values, a quaternion off unit norm, empty nodes (unless `skip_empty`), or
/// trailing bytes.
[[nodiscard]] PointCloudSet decodeScanGraph(std::string_view bytes, const std::filesystem::path& file,
                                            bool skip_empty = false);
[[nodiscard]] Dataset importScanGraph(const std::filesystem::path& file, bool skip_empty = false);

}  // namespace occsweep
