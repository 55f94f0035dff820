// Registers the example method and sweeps a data set with it, as `occsweep sweep` would:
//   sweep_example_method DATASET_DIR GRID.json OUT.json
// `occsweep compare` then reads OUT.json beside OctoMap's results (results files name their parameters).
#include <iostream>
#include <memory>

#include <occsweep/core/method_registry.hpp>
#include <occsweep/methods/builtin_methods.hpp>
#include <occsweep/sweeps/sweep.hpp>

#include "example_method.hpp"

int main(int argc, char** argv) {
  if (argc != 4) {
    std::cerr << "usage: sweep_example_method DATASET_DIR GRID.json OUT.json\n";
    return 2;
  }
  occsweep::registerBuiltinMethods();  // occsweep's own, beside the example's (compare reads both)
  occsweep::registerMethod(std::make_shared<DensityOctoMapMethod>());
  occsweep::SweepConfig config;
  config.dataset = argv[1];
  config.grid = argv[2];
  config.out = argv[3];
  config.quiet = true;
  const occsweep::ResultsFile results = occsweep::runSweep(config);
  double best = 0.0;
  for (const auto& m : results.maps) best = std::max(best, m.area.anchored);
  std::cout << "density-octomap: " << results.maps.size() << " maps swept by the " << results.header.engine
            << " engine, best AUC " << best << '\n';
  return 0;
}
