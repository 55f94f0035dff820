#include "occsweep/data/octree_file.hpp"

#include <cmath>
#include <cstring>
#include <sstream>
#include <vector>

#include "occsweep/core/limits.hpp"
#include "occsweep/io/bounded_read.hpp"
#include "occsweep/data/byte_reader.hpp"

namespace occsweep {
namespace {

constexpr int kTreeDepth = 16;          // liboctomap's OcTree
constexpr std::size_t kNodeBytes = 5;   // float log-odds + one byte of child bits (OcTreeBaseImpl::readNodesRecurs)

struct OtHeader {
  std::string id;
  double resolution = 0.0;
  std::uint64_t size = 0;
  std::size_t data_offset = 0;
};

// The header as AbstractOcTree::readHeader reads it: whitespace-separated keywords, '#' comment lines, up to "data".
OtHeader parseOtHeader(std::string_view bytes, const std::filesystem::path& file) {
  constexpr std::string_view kMagic = "# Octomap OcTree file";
  if (bytes.substr(0, kMagic.size()) != kMagic)
    throw DataError(file, "magic", "not an OctoMap .ot file: must start with \"# Octomap OcTree file\"");
  TextLines lines(bytes, file);
  std::vector<std::string_view> tokens;
  lines.next(tokens);
  OtHeader h;
  bool has_res = false, has_size = false;
  while (lines.next(tokens)) {
    if (tokens.empty() || tokens[0].front() == '#') continue;
    if (tokens[0] == "data") {
      if (tokens.size() != 1) lines.fail("\"data\" must stand alone on its line");
      h.data_offset = lines.offset();
      if (h.id != "OcTree") lines.fail("tree type \"" + h.id + "\": only OcTree maps are read");
      if (!has_res || !has_size) lines.fail("the header needs res and size before data");
      return h;
    }
    if (tokens.size() != 2) lines.fail("header lines are \"KEYWORD VALUE\"");
    if (tokens[0] == "id") {
      h.id = std::string(tokens[1]);
    } else if (tokens[0] == "res") {
      h.resolution = lines.number(tokens[1], 2, "res");
      if (!(h.resolution > 0.0)) lines.fail("res must be > 0");
      has_res = true;
    } else if (tokens[0] == "size") {
      if (!parseUnsigned(tokens[1], h.size)) lines.fail("size must be a non-negative integer");
      has_size = true;
    }  // other keywords: skipped, as liboctomap does
  }
  throw DataError(file, "header", "no \"data\" line: truncated file");
}

// Walks the pre-order node stream without building anything: every node's bytes present, no node below the
// finest depth, no NaN; counts the finest-depth voxels the leaves stand for (a leaf at depth d: 8^(16-d)).
std::size_t walkNodes(std::string_view data, std::size_t base, const std::filesystem::path& file) {
  std::uint64_t voxels = 0;
  std::size_t pos = 0;
  std::vector<int> pending;  // per open depth, the children still to read
  int depth = 0;
  pending.push_back(1);      // the root
  while (!pending.empty()) {
    if (pending.back() == 0) {
      pending.pop_back();
      --depth;
      continue;
    }
    --pending.back();
    if (data.size() - pos < kNodeBytes)
      throw DataError(file, "byte " + std::to_string(base + pos),
                      "a node needs 5 bytes, only " + std::to_string(data.size() - pos) + " left: truncated file");
    float value;
    std::memcpy(&value, data.data() + pos, sizeof value);
    if (std::isnan(value)) throw DataError(file, "byte " + std::to_string(base + pos), "node value is NaN");
    const auto children = static_cast<unsigned char>(data[pos + 4]);
    pos += kNodeBytes;
    const int child_count = __builtin_popcount(children);
    if (child_count == 0) {
      voxels += std::uint64_t(1) << (3 * (kTreeDepth - depth));  // at most 8^16 = 2^48: no overflow
      if (voxels > limits().map_voxels)
        throw DataError(file, "byte " + std::to_string(base + pos - kNodeBytes),
                        LimitError("voxels at the finest depth, counted so far", voxels, limits().map_voxels,
                                   "--max-map-voxels")
                            .what());
      continue;
    }
    if (depth == kTreeDepth)
      throw DataError(file, "byte " + std::to_string(base + pos - 1),
                      "a node at the finest depth (16) has children: corrupt file");
    pending.push_back(child_count);
    ++depth;
  }
  return pos;
}

}  // namespace

std::unique_ptr<octomap::OcTree> decodeOcTree(std::string_view bytes, const std::filesystem::path& file) {
  const OtHeader h = parseOtHeader(bytes, file);
  auto tree = std::make_unique<octomap::OcTree>(h.resolution);
  if (h.size == 0) return tree;  // liboctomap writes no node stream for an empty tree
  const std::string_view data = bytes.substr(h.data_offset);
  const std::size_t used = walkNodes(data, h.data_offset, file);
  if (used != data.size())
    throw DataError(file, "byte " + std::to_string(h.data_offset + used),
                    std::to_string(data.size() - used) + " bytes after the last node: not one OcTree");
  std::istringstream in(std::string(data), std::ios::binary);
  tree->readData(in);
  if (!in) throw DataError(file, "data", "liboctomap could not read the nodes");
  return tree;
}

std::unique_ptr<octomap::OcTree> readOcTree(const std::filesystem::path& file) {
  return decodeOcTree(readFileBytes(file), file);
}

}  // namespace occsweep
