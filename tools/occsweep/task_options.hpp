// The options of the commands a cluster plan runs (sweep, merge, compare, cluster select), registered in one place
// each: the commands use them, and so does tests/tools/test_cluster_argv.cpp, which checks that parsing the argv that
// taskArgv (occsweep/sweeps/cluster_tasks.hpp) renders gives back the task.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "map_setting_flags.hpp"
#include "occsweep/sweeps/cluster_tasks.hpp"

namespace occsweep::cli {

/// `sweep`'s options as parsed; sweepConfigOf turns them into the SweepConfig.
struct SweepOptions {
  SweepConfig config;
  std::vector<std::string> grids, outs;  ///< one --out per --grid, in order (several: sweepGrids)
  MapSettingFlags map;
  std::string dataset, shard, group, truth = truthModeName(TruthMode::Full);
  std::uint64_t seed = 0;
};

/// Every option of `sweep` that is part of SweepConfig (the limit flags are the command's own). None is required
/// here: `sweep` requires --dataset, --grid and --out, `cluster plan --sweep-args` forbids them.
void addSweepOptions(CLI::App& app, SweepOptions& o);
/// The sweeps the parsed options describe, one per --grid with its --out. std::invalid_argument for a bad --shard or
/// --group, or unless there are as many --out as --grid.
[[nodiscard]] std::vector<SweepConfig> sweepConfigsOf(const SweepOptions& o);
/// The one sweep they describe: the inverse of taskArgv(SweepConfig) (at most one --grid and --out).
[[nodiscard]] SweepConfig sweepConfigOf(const SweepOptions& o);
/// `cluster plan --sweep-args`: the settings every sweep of a plan shares, parsed as `sweep` parses them. The
/// options the plan sets itself (--dataset, --grid, --out, --shard, --group, --seed, --threads, --force) are refused.
[[nodiscard]] SweepConfig sharedSweepSettings(const std::vector<std::string>& args);

void addMergeOptions(CLI::App& app, MergeTask& task);
void addCompareOptions(CLI::App& app, CompareTask& task);
void addSelectOptions(CLI::App& app, SelectTask& task);

}  // namespace occsweep::cli
