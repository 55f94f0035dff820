// What the sweep tests sweep: the small built-in scene (6 scans of 32 x 24 rays, written as a data set under `dir`),
// and a quiet sweep config.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

#include "occsweep/eval/builtin_scene.hpp"
#include "occsweep/eval/dataset.hpp"
#include "occsweep/sweeps/sweep.hpp"

namespace occsweep::test {

inline std::filesystem::path smallScene(const std::filesystem::path& dir, std::uint64_t seed = 3) {
  const std::filesystem::path path = dir / ("scene" + std::to_string(seed));
  writeDataset(makeBuiltinScene({.seed = seed, .scans = 6, .width = 32, .height = 24}), path);
  return path;
}

/// A quiet sweep of `grid` on `data` into `out`, shard `shard` of `shards`.
inline SweepConfig quietSweep(const std::filesystem::path& data, const std::string& grid,
                              const std::filesystem::path& out, std::uint64_t shard = 0, std::uint64_t shards = 1) {
  SweepConfig c;
  c.dataset = data;
  c.grid = grid;
  c.out = out;
  c.selection.shard_index = shard;
  c.selection.shard_count = shards;
  c.quiet = true;
  return c;
}

}  // namespace occsweep::test
