// occsweep sweep: every combination of a grid on one data set, as a results file (docs/definitions.md, Results files);
// several grids at once share the data set's read and recording (sweepGrids).
#include <iostream>

#include "command_registry.hpp"
#include "limit_options.hpp"
#include "task_options.hpp"

namespace occsweep::cli {
namespace {

const RegisterCommand kSweep{"sweep", "Sweep a parameter grid on a data set: one map per combination but p_t",
                             [](CLI::App& app) {
  auto o = std::make_shared<SweepOptions>();
  addSweepOptions(app, *o);  // task_options.cpp: also what `cluster plan` tasks are parsed with
  for (const char* needed : {"--dataset", "--grid", "--out"}) app.get_option(needed)->required();
  addLimitOptions(app, {Limit::WindowVoxels, Limit::Combinations, Limit::RegionVoxels, Limit::Points});
  return [o] {
    const std::vector<SweepConfig> configs = sweepConfigsOf(*o);
    const std::vector<SweepSummary> written = sweepGrids(configs);
    for (std::size_t i = 0; i < written.size(); ++i)
      std::cout << "wrote " << configs[i].out.string() << ": " << written[i].maps << " maps, " << written[i].combinations
                << " combinations of " << written[i].header.grid_name << " in " << written[i].seconds << " s\n";
    return 0;
  };
}};

}  // namespace
}  // namespace occsweep::cli
