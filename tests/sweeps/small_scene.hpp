// The small built-in scene the sweep tests sweep: 6 scans of 32 x 24 rays, written as a data set under `dir`.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

#include "occsweep/eval/builtin_scene.hpp"
#include "occsweep/eval/dataset.hpp"

namespace occsweep::test {

inline std::filesystem::path smallScene(const std::filesystem::path& dir, std::uint64_t seed = 3) {
  const std::filesystem::path path = dir / ("scene" + std::to_string(seed));
  writeDataset(makeBuiltinScene({.seed = seed, .scans = 6, .width = 32, .height = 24}), path);
  return path;
}

}  // namespace occsweep::test
