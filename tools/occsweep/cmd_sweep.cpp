// occsweep sweep: every combination of a grid on one data set, as a results file (docs/definitions.md, Results files);
// several grids at once share the data set's read and recording (sweepGrids).
#include <cstdint>
#include <iostream>
#include <stdexcept>

#include "command_registry.hpp"
#include "coverage_report.hpp"
#include "limit_options.hpp"
#include "task_options.hpp"
#include "occsweep/sweeps/results_file.hpp"
#include "occsweep/sweeps/selection.hpp"
#include "occsweep/sweeps/sweep.hpp"
#include "occsweep/io/control_characters.hpp"

namespace occsweep::cli {
namespace {

/// The combinations a sweep writes: the grid's (Eq. 15, not enumerated), or its selection's when that is smaller;
/// 0 for a selection past --max-combinations, which the sweep refuses by that limit's own message.
std::uint64_t sweptCombinations(const SweepConfig& c) {
  const GridSpec grid = loadGrid(resolveGridPath(c.grid));
  const std::uint64_t all = combinationCount(grid);
  if (c.selection == SweepSelection{}) return all > limits().combinations ? 0 : all;
  if (all <= kMaxJsonCombinations) return all;
  std::uint64_t selected = 0;
  try {
    for (const SweepItem& item : selectWork(grid, enumerateSelection(grid, c.selection), c.selection))
      selected += item.thresholds.size();
  } catch (const LimitError&) {
    return 0;
  }
  return selected;
}

/// Before anything is read or written: a JSON --out past kMaxJsonCombinations is refused, pointing at a store.
void refuseLargeJson(const SweepConfig& c) {
  if (!isStorePath(c.out)) occsweep::refuseLargeJson(c.out, "this sweep of " + c.grid, sweptCombinations(c));
}

const RegisterCommand kSweep{"sweep", "Sweep a parameter grid on a data set: one map per combination but p_t",
                             [](CLI::App& app) {
  addExample(app, "occsweep sweep --dataset ds --grid octomap-opt --grid knn-opt --out oct.json --out knn.json");
  auto o = std::make_shared<SweepOptions>();
  addSweepOptions(app, *o);  // task_options.cpp: also what `cluster plan` tasks are parsed with
  for (const char* needed : {"--dataset", "--grid", "--out"}) app.get_option(needed)->required();
  addLimitOptions(app, {Limit::WindowVoxels, Limit::Combinations, Limit::RegionVoxels, Limit::Points,
                        Limit::NeighbourDistances, Limit::JsonBytes});
  return [o] {
    const std::vector<SweepConfig> configs = sweepConfigsOf(*o);
    for (const SweepConfig& c : configs) refuseLargeJson(c);
    const std::vector<SweepSummary> written = sweepGrids(configs);
    for (std::size_t i = 0; i < written.size(); ++i)
      std::cout << "wrote " << escapedControlCharacters(configs[i].out.string()) << ": " << written[i].maps << " maps, " << written[i].combinations
                << " combinations of " << written[i].header.grid_name << " in " << written[i].seconds << " s\n";
    // one data set for every grid: its coverage once (none recorded in a complete file of an older occsweep)
    for (const SweepSummary& s : written)
      if (s.header.coverage) {
        reportCoverage(*s.header.coverage, s.header.truth, "occsweep sweep", configs.front().dataset.string());
        break;
      }
    return 0;
  };
}, "the maps it finished are kept beside each output (NAME.partial.jsonl or NAME.db.partial)"};

}  // namespace
}  // namespace occsweep::cli
