// How a map a results file scored is built again: its method, its values and the settings every map shares, all
// taken from the file (docs/methods.md, "One map"). `occsweep map --from` and the reproduction's Fig. 6 maps use it.
#pragma once

#include <string>

#include "occsweep/core/method_registry.hpp"
#include "occsweep/sweeps/results.hpp"

namespace occsweep {

/// One scored map, ready for its method's buildMap.
struct ScoredMapRecipe {
  const MappingMethod* method = nullptr;
  MethodValues values;  ///< in the order of method->parameters()
  MapContext context;   ///< resolution, s_c, variant and statistics mode of the results file
};

/// The recipe of `map`, a map of the results file `file` whose header is `header`. Throws std::invalid_argument
/// naming `file` and the map when its method is not registered or a relation of the method fails.
[[nodiscard]] ScoredMapRecipe scoredMapRecipe(const ResultsHeader& header, const MapResult& map,
                                              const std::string& file);

}  // namespace occsweep
