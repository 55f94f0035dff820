// A scored map's method, values and settings from its results file (map_recipe.hpp).
#include "occsweep/sweeps/map_recipe.hpp"

#include <stdexcept>

namespace occsweep {

ScoredMapRecipe scoredMapRecipe(const ResultsHeader& header, const MapResult& map, const std::string& file) {
  ScoredMapRecipe r;
  try {
    r.method = &findMethod(header.method);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(file + ": " + e.what());
  }
  for (const MethodParameter& p : r.method->parameters())
    r.values.push_back(parameterValue(header.parameters, map.params, p.name));
  if (auto why = brokenRelation(*r.method, r.values))
    throw std::invalid_argument(file + ": map " + std::to_string(map.map_index) + ": " + *why);
  r.context.map = header.map;
  return r;
}

}  // namespace occsweep
