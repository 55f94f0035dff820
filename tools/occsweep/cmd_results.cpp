// occsweep results check FILE: exit 0 only for a complete, consistent results file.
#include <iostream>

#include "command_registry.hpp"
#include "occsweep/sweeps/merge.hpp"
#include "occsweep/sweeps/results_verify.hpp"

namespace occsweep::cli {
namespace {

const RegisterCommand kResults{"results", "Check results files", [](CLI::App& app) {
  auto file = std::make_shared<std::string>();
  CLI::App* check = app.add_subcommand("check", "Exit 0 when FILE is a complete, consistent results file (docs/results-format.md)");
  auto dataset = std::make_shared<std::string>();
  check->add_option("file", *file, "Results file")->required();
  check->add_option("--dataset", *dataset, "Also check against this data set: its content hash, and every threshold "
                                           "counting its region's and its truth's voxels");
  app.require_subcommand(1);
  return [=] {
    return runChosen({{check, [=] {
                         const ResultsFile f = readResults(*file);
                         if (!f.complete) throw std::runtime_error(*file + ": incomplete results");
                         const bool grid_checked = checkAgainstGrid(f, *file);
                         if (!dataset->empty()) verifyAgainstDataset(f, *file, *dataset);
                         // docs/results-format.md lists what each line vouches for.
                         std::cout << *file << ": complete, " << f.maps.size() << " maps";
                         if (grid_checked)
                           std::cout << ", every map and threshold of the selection once, parameters match grid ";
                         else if (f.header.selection.shard_count == 1)
                           std::cout << ", every id of the selection once; grid file not found, parameters not "
                                        "checked against grid ";
                         else
                           std::cout << "; grid file not found: parameters and the shard's maps not checked against "
                                        "grid ";
                         std::cout << f.header.grid_name;
                         if (f.header.truth == TruthMode::Observable) std::cout << ", observable truth (map.truth)";
                         if (!dataset->empty()) std::cout << "; counts match the region and truth of " << *dataset;
                         std::cout << '\n';
                         return 0;
                       }}});
  };
}};

}  // namespace
}  // namespace occsweep::cli
