// occsweep results check FILE: exit 0 only for a complete, consistent results file.
#include <iostream>

#include "command_registry.hpp"
#include "occsweep/sweeps/merge.hpp"

namespace occsweep::cli {
namespace {

const RegisterCommand kResults{"results", "Check results files", [](CLI::App& app) {
  auto file = std::make_shared<std::string>();
  CLI::App* check = app.add_subcommand("check", "Exit 0 when FILE is a complete, consistent results file");
  check->add_option("file", *file, "Results file")->required();
  app.require_subcommand(1);
  return [=] {
    return runChosen({{check, [=] {
                         const ResultsFile f = readResults(*file);
                         if (!f.complete) throw std::runtime_error(*file + ": incomplete results");
                         const bool grid_checked = checkAgainstGrid(f, *file);
                         std::cout << *file << ": complete, " << f.maps.size() << " maps"
                                   << (grid_checked ? ", parameters match grid " : ", grid file not found: ")
                                   << f.header.grid_name << '\n';
                         return 0;
                       }}});
  };
}};

}  // namespace
}  // namespace occsweep::cli
