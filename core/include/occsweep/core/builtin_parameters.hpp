// The parameters of OctoMap and of the k-NN model as data: names, defaults, bounds and Eq. 12's relations, written
// once. OctoMapMethod and KnnMethod (builtin_methods.hpp) declare these, and their mappers' settings
// (mapping_params.hpp) take their defaults and their checks from them. Defaults: liboctomap's own (OcTree's
// constructor), clamping thresholds rounded to the paper's two decimals; the k-NN model's as in the paper's Table 1.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "method_parameter.hpp"

namespace occsweep::builtin {

/// The parameters every OctoMap-family method shares, with Eq. 12's bounds.
[[nodiscard]] inline MethodParameter clampMax() {
  return {"p_max", "p_max", "upper clamping threshold", 0.97, 0.5, 1.0, false, true, false, "Eq. 12"};
}
[[nodiscard]] inline MethodParameter clampMin() {
  return {"p_min", "p_min", "lower clamping threshold", 0.12, 0.0, 0.5, true, true, false, "Eq. 12"};
}
[[nodiscard]] inline MethodParameter missIn() {
  return {"p_m", "p_m", "miss: voxels crossed by a ray to an in-range point", 0.4, 0.0, 0.5, true, true, false,
          "Eq. 12"};
}
[[nodiscard]] inline MethodParameter hitProbability() {
  return {"p_h", "p_h", "hit: voxels holding an in-range point", 0.7, 0.5, 1.0, false, true, false, "Eq. 12"};
}

/// OctoMap (Eq. 4-5), in the order grids enumerate them.
[[nodiscard]] inline std::vector<MethodParameter> octomapParameters() {
  return {clampMax(), clampMin(), hitProbability(), missIn()};
}
/// Eq. 12 for OctoMap beyond the bounds: p_max >= p_h, p_m >= p_min.
[[nodiscard]] inline std::vector<ParameterRelation> octomapRelations() {
  return {{"p_max", "p_h", false, "Eq. 12"}, {"p_m", "p_min", false, "Eq. 12"}};
}

/// The k-NN inverse sensor model (Eq. 6-10, Algorithm 1), in the order grids enumerate them.
[[nodiscard]] inline std::vector<MethodParameter> knnParameters() {
  return {{"k", "k", "neighbours averaged into s_j", 3, 1, 100000, false, false, true, "Section 3.1"},
          {"p_u", "p_u", "upper bound of p(s): a point with tight neighbours", 0.86, 0, 1, true, true, false,
           "l(p(s)) finite"},
          {"p_l", "p_l", "lower bound of p(s): an isolated point", 0.26, 0, 1, true, true, false, "l(p(s)) finite"},
          clampMax(),
          clampMin(),
          missIn(),
          {"p_m_out", "p'_m", "miss: voxels crossed only by rays to points beyond s_c", 0.45, 0, 0.5, true, true,
           false, "Eq. 12"}};
}
/// Eq. 12 for k-NN beyond the bounds: p_u >= p_l, p_m >= p_min, p'_m >= p_m.
[[nodiscard]] inline std::vector<ParameterRelation> knnRelations() {
  return {{"p_u", "p_l", false, "Eq. 12"}, {"p_m", "p_min", false, "Eq. 12"}, {"p_m_out", "p_m", false, "Eq. 12"}};
}

/// The default of parameter `name` among `parameters`.
[[nodiscard]] inline double defaultOf(const std::vector<MethodParameter>& parameters, const std::string& name) {
  for (const MethodParameter& p : parameters)
    if (p.name == name) return p.default_value;
  throw std::logic_error("no built-in parameter " + name);
}

}  // namespace occsweep::builtin
