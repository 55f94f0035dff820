#include "occsweep/stereo/pointcloud_grid.hpp"

#include <algorithm>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

#include "occsweep/io/bounded_read.hpp"
#include "occsweep/io/fnv1a.hpp"

namespace occsweep::stereo {
namespace {

constexpr const char* kKeys[5] = {"blockSize", "uniquenessRatio", "speckleWindowSize", "speckleRange", "disp12MaxDiff"};

std::vector<int>* listFor(PointCloudGrid& g, int i) {
  std::vector<int>* lists[5] = {&g.block_size, &g.uniqueness_ratio, &g.speckle_window_size, &g.speckle_range,
                                &g.disp12_max_diff};
  return lists[i];
}

}  // namespace

std::uint64_t PointCloudGrid::size() const {
  return std::uint64_t(block_size.size()) * uniqueness_ratio.size() * speckle_window_size.size() *
         speckle_range.size() * disp12_max_diff.size();
}

SgbmParams PointCloudGrid::at(std::uint64_t id) const {
  if (id >= size()) throw std::out_of_range("point cloud parameter id " + std::to_string(id) + " is not below " +
                                            std::to_string(size()));
  SgbmParams p;
  p.disp12_max_diff = disp12_max_diff[id % disp12_max_diff.size()], id /= disp12_max_diff.size();
  p.speckle_range = speckle_range[id % speckle_range.size()], id /= speckle_range.size();
  p.speckle_window_size = speckle_window_size[id % speckle_window_size.size()], id /= speckle_window_size.size();
  p.uniqueness_ratio = uniqueness_ratio[id % uniqueness_ratio.size()], id /= uniqueness_ratio.size();
  p.block_size = block_size[id];
  return p;
}

PointCloudGrid parsePointCloudGrid(const nlohmann::json& j, const std::string& file) {
  auto fail = [&](const std::string& key, const std::string& rule) -> std::runtime_error {
    return std::runtime_error(file + ": " + key + ": " + rule);
  };
  if (!j.is_object()) throw fail("(top level)", "must be a JSON object");
  for (const auto& [key, value] : j.items())
    if (key != "name" && key != "kind" && key != "description" && key != "parameters") throw fail(key, "unknown key");
  if (!j.contains("kind") || j["kind"] != "stereo-sgbm") throw fail("kind", "must be \"stereo-sgbm\"");
  if (!j.contains("name") || !j["name"].is_string()) throw fail("name", "must be a string");
  if (!j.contains("parameters") || !j["parameters"].is_object()) throw fail("parameters", "must be an object");
  PointCloudGrid g;
  g.name = j["name"].get<std::string>();
  const auto& params = j["parameters"];
  for (const auto& item : params.items()) {
    const std::string& key = item.key();  // not a structured binding: clang 14 cannot capture one in a lambda
    if (std::find_if(std::begin(kKeys), std::end(kKeys), [&](const char* k) { return key == k; }) == std::end(kKeys))
      throw fail("parameters." + key, "unknown parameter");
  }
  for (int i = 0; i < 5; ++i) {
    const std::string key = std::string("parameters.") + kKeys[i];
    if (!params.contains(kKeys[i])) throw fail(key, "missing");
    const auto& list = params[kKeys[i]];
    if (!list.is_array() || list.empty()) throw fail(key, "must be a non-empty list of integers");
    std::set<int> seen;
    for (const auto& v : list) {
      if (!v.is_number_integer()) throw fail(key, "must be a non-empty list of integers");
      const int x = v.get<int>();
      if (!seen.insert(x).second) throw fail(key, "value " + std::to_string(x) + " is repeated");
      listFor(g, i)->push_back(x);
    }
  }
  for (std::uint64_t id = 0; id < g.size(); id += 1) {
    try {
      validate(g.at(id));
    } catch (const std::invalid_argument& e) {
      throw fail("parameters", e.what());
    }
  }
  return g;
}

PointCloudGrid loadPointCloudGrid(const std::filesystem::path& file) {
  // readFileBytes refuses a FIFO or a device by name, which a stream would wait on forever.
  const std::string bytes = readFileBytes(file);
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(bytes);
  } catch (const nlohmann::json::parse_error& e) {
    throw std::runtime_error(file.string() + ": not valid JSON: " + e.what());
  }
  PointCloudGrid g = parsePointCloudGrid(j, file.string());
  Fnv1a h;
  h.feed(bytes);
  g.file_hash = h.hex();
  return g;
}

std::vector<std::uint64_t> evenSubset(std::uint64_t size, std::uint64_t count) {
  std::vector<std::uint64_t> ids;
  if (count >= size) {
    for (std::uint64_t i = 0; i < size; ++i) ids.push_back(i);
    return ids;
  }
  if (count == 1) return {0};
  for (std::uint64_t i = 0; i < count; ++i) ids.push_back((2 * i * (size - 1) + (count - 1)) / (2 * (count - 1)));
  return ids;
}

}  // namespace occsweep::stereo
