// occsweep merge: the shards of one sweep into one results file, every combination exactly once.
#include <iostream>

#include "command_registry.hpp"
#include "limit_options.hpp"
#include "occsweep/sweeps/merge.hpp"

namespace occsweep::cli {
namespace {

const RegisterCommand kMerge{"merge", "Merge the shards of one sweep (refuses missing, duplicated, foreign work)",
                             [](CLI::App& app) {
  auto files = std::make_shared<std::vector<std::string>>();
  auto out = std::make_shared<std::string>();
  auto force = std::make_shared<bool>(false);
  app.add_option("files", *files, "Results files of one sweep's shards")->required();
  app.add_option("--out", *out, "Merged results file")->required();
  app.add_flag("--force", *force, "Replace occsweep's own previous results file at --out (nothing else)");
  addLimitOptions(app, {Limit::Combinations});
  return [files, out, force] {
    checkOutputTarget(*out, *force, resultsOutput());
    const ResultsFile merged = mergeResults({files->begin(), files->end()});
    writeResults(merged, *out);
    std::cout << "wrote " << *out << ": " << merged.maps.size() << " maps from " << files->size() << " files\n";
    return 0;
  };
}};

}  // namespace
}  // namespace occsweep::cli
