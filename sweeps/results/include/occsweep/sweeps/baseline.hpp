// The method every other one is compared with unless a command is told otherwise (compare --baseline, plot
// --baseline): OctoMap, the paper's baseline (docs/statistics.md). A name only: results name their method.
#pragma once

#include <string>

namespace occsweep {

inline const std::string kDefaultBaseline = "octomap";

}  // namespace occsweep
