// occsweep sweep: every combination of a grid on one data set, as a results file (docs/definitions.md, Results files).
#include <iostream>

#include "command_registry.hpp"
#include "option_checks.hpp"
#include "limit_options.hpp"
#include "occsweep/sweeps/sweep.hpp"
#include "occsweep/sweeps/sweep_engine.hpp"
#include "selection_options.hpp"

namespace occsweep::cli {
namespace {

const RegisterCommand kSweep{"sweep", "Sweep a parameter grid on a data set: one map per combination but p_t",
                             [](CLI::App& app) {
  struct Options {
    SweepConfig config;
    std::string dataset, out, shard, group, variant = toText(UpdateVariant::Default),
                                            stats = toText(StatsMode::Batch), truth = truthModeName(TruthMode::Full);
    std::uint64_t seed = 0;
    bool force = false;
  };
  auto o = std::make_shared<Options>();
  app.add_option("--dataset", o->dataset, "Data-set folder")->required();
  app.add_option("--grid", o->config.grid, "Grid name (sweeps/grids) or path")->required();
  app.add_option("--out", o->out, "Results file (JSON); the same sweep's own file or OUT.partial.jsonl resumes")->required();
  app.add_flag("--force", o->force, "Replace occsweep's own results of other work at --out (nothing else)");
  app.add_option("--shard", o->shard, "I/N: the I-th of N contiguous blocks of the grid's maps (I from 0)");
  app.add_option("--group", o->group, "G/N: only the G-th Eq. 16 group of the seeded permutation");
  app.add_option("--seed", o->seed, "Seed of the Eq. 16 permutation (with --group)")->capture_default_str();
  app.add_option("--resolution", o->config.resolution, "Map resolution, metres")->capture_default_str()->check(numberAbove(0));
  app.add_option("--s-c", o->config.s_c, "Maximum range s_c, metres")->capture_default_str()->check(numberAbove(0));
  app.add_option("--variant", o->variant, "k-NN update variant")
      ->check(CLI::IsMember(kUpdateVariantNames.list()))->capture_default_str();
  app.add_option("--stats", o->stats, "k-NN mu, sigma source")
      ->check(CLI::IsMember(kStatsModeNames.list()))->capture_default_str();
  app.add_option("--threads", o->config.threads, "Worker threads (0: all cores)")->capture_default_str()->check(integerAtLeast<int>(0));
  app.add_option("--engine", o->config.engine, "replay: record events once, replay every combination; direct: build every map (the reference)")
      ->check(CLI::IsMember(sweepEngineNames()))->capture_default_str();
  app.add_option("--truth", o->truth, "full: every truth voxel counts; observable: only those a ray from a scan origin "
                                      "reaches within s_c before any other truth voxel (docs/results-format.md)")
      ->check(CLI::IsMember(kTruthModeNames.list()))->capture_default_str();
  app.add_flag("--quiet", o->config.quiet, "No progress on stderr");
  addLimitOptions(app, {Limit::WindowVoxels, Limit::Combinations, Limit::RegionVoxels, Limit::Points});
  return [o] {
    SweepConfig c = o->config;
    c.dataset = o->dataset;
    c.out = o->out;
    c.force = o->force;
    if (!o->shard.empty()) std::tie(c.selection.shard_index, c.selection.shard_count) = parseFraction(o->shard, "--shard");
    if (!o->group.empty()) {
      const auto [g, n] = parseFraction(o->group, "--group");
      c.selection.group = SweepSelection::Group{g, n, o->seed};
    }
    c.variant = parseUpdateVariant(o->variant);
    c.stats = parseStatsMode(o->stats);
    c.truth = parseTruthMode(o->truth);
    const ResultsFile r = runSweep(c);
    std::size_t combinations = 0;
    for (const auto& m : r.maps) combinations += m.thresholds.size();
    std::cout << "wrote " << o->out << ": " << r.maps.size() << " maps, " << combinations << " combinations of "
              << r.header.grid_name << " in " << r.seconds << " s\n";
    return 0;
  };
}};

}  // namespace
}  // namespace occsweep::cli
