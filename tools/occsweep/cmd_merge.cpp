// occsweep merge: the shards of one sweep into one results file, every combination exactly once.
#include <iostream>

#include "command_registry.hpp"
#include "limit_options.hpp"
#include "task_options.hpp"
#include "occsweep/io/output_file.hpp"
#include "occsweep/sweeps/merge.hpp"
#include "occsweep/io/control_characters.hpp"

namespace occsweep::cli {
namespace {

const RegisterCommand kMerge{"merge", "Merge the shards of one sweep (refuses missing, duplicated, foreign work)",
                             [](CLI::App& app) {
  addExample(app, "occsweep sweep --dataset ds --grid knn-opt --shard 0/2 --out s0.json\noccsweep sweep --dataset ds --grid knn-opt --shard 1/2 --out s1.json\noccsweep merge s0.json s1.json --out merged.json");
  auto t = std::make_shared<MergeTask>();
  addMergeOptions(app, *t);  // task_options.cpp: also what `cluster plan` tasks are parsed with
  addLimitOptions(app, {Limit::Combinations, Limit::JsonBytes});
  return [t] {
    for (const std::string& in : t->files)  // --force would replace a shard before it is read
      if (outputsCollide(in, t->out))
        throw OutputError("--out " + t->out + ": is one of the files to merge (" + in + "); choose another --out");
    checkOutputTarget(t->out, t->force, resultsOutput());
    const std::uint64_t maps = mergeResultsInto({t->files.begin(), t->files.end()}, t->out);
    std::cout << "wrote " << escapedControlCharacters(t->out) << ": " << maps << " maps from " << t->files.size() << " files\n";
    return 0;
  };
}};

}  // namespace
}  // namespace occsweep::cli
