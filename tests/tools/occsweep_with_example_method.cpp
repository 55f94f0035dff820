// occsweep with one more method: examples/occupancy_method's density-octomap, registered from outside the library
// before the command line runs, as a program with a method of its own does (docs/methods.md, "Bring your own
// method"). test_map_methods maps and sweeps it through every command.
#include <memory>

#include "command_line.hpp"
#include "example_method.hpp"
#include "occsweep/core/method_registry.hpp"

int main(int argc, char** argv) {
  occsweep::registerMethod(std::make_shared<DensityOctoMapMethod>());
  return occsweep::cli::runCommandLine(argc, argv);
}
