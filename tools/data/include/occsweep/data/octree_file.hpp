// OctoMap .ot files read with every count checked: liboctomap's reader trusts the bytes (a truncated file or
// 0xff bytes can make it allocate gigabytes), so the structure is walked and bounded here first.
#pragma once

#include <filesystem>
#include <memory>
#include <string_view>

#include <octomap/OcTree.h>

namespace occsweep {

/// An OcTree from the bytes of a .ot file (AbstractOcTree's format: a "# Octomap OcTree file" line, header lines
/// id/size/res, "data", then the nodes in pre-order, each a float log-odds and a byte of child bits). DataError
/// naming the file and the byte or field for: another tree type, a bad resolution, a truncated or over-long node
/// stream, a node deeper than 16 levels, a NaN value, or a map whose finest-depth voxels (as expand() makes them)
/// exceed limits().map_voxels (--max-map-voxels). Nothing is allocated for the tree before the walk passes.
[[nodiscard]] std::unique_ptr<octomap::OcTree> decodeOcTree(std::string_view bytes, const std::filesystem::path& file);

/// readFileBytes (regular files only), then decodeOcTree.
[[nodiscard]] std::unique_ptr<octomap::OcTree> readOcTree(const std::filesystem::path& file);

}  // namespace occsweep
