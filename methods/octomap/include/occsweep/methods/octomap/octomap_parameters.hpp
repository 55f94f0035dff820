// OctoMap's parameters as data (names, defaults, bounds and Eq. 12's relations, written once) and the settings of
// its mapper, which take their defaults and their checks from them. Defaults: liboctomap's own (OcTree's
// constructor), clamping thresholds rounded to the paper's two decimals. The other OctoMap-family methods share
// the clamping, hit and miss parameters declared here.
#pragma once

#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "occsweep/core/map_settings.hpp"
#include "occsweep/core/method_parameter.hpp"

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

/// The default of parameter `name` among `parameters`.
[[nodiscard]] inline double defaultOf(const std::vector<MethodParameter>& parameters, const std::string& name) {
  for (const MethodParameter& p : parameters)
    if (p.name == name) return p.default_value;
  throw std::logic_error("no built-in parameter " + name);
}

}  // namespace occsweep::builtin

namespace occsweep {

namespace detail {
[[nodiscard]] double octomapDefault(const std::string& name);
}  // namespace detail

/// Parameters of the OctoMap baseline (Eq. 4-5), by liboctomap's setters.
struct OctoMapParams {
  double p_h = detail::octomapDefault("p_h");      ///< probability of a hit (setProbHit)
  double p_m = detail::octomapDefault("p_m");      ///< probability of a miss (setProbMiss)
  double p_max = detail::octomapDefault("p_max");  ///< upper clamping threshold (setClampingThresMax)
  double p_min = detail::octomapDefault("p_min");  ///< lower clamping threshold (setClampingThresMin)
  double p_t = 0.5;  ///< occupancy threshold (setOccupancyThres): occupied when l >= l(p_t); liboctomap's default
  MapSettings map;   ///< resolution and s_c (OctoMap reads neither the variant nor the statistics mode)
};

/// The first setting, bound or relation of Eq. 12 the parameters break, as a sentence naming it; none if valid.
[[nodiscard]] std::optional<std::string> brokenRelation(const OctoMapParams& p);

/// Throws std::invalid_argument naming the broken relation.
template <class Params>
void validate(const Params& p) {
  if (auto why = brokenRelation(p)) throw std::invalid_argument(*why);
}

// ---------------------------------------------------------------------------------------------------------
namespace detail {

inline double octomapDefault(const std::string& name) {
  static const std::vector<MethodParameter> parameters = builtin::octomapParameters();
  return builtin::defaultOf(parameters, name);
}

// The values of `parameters` in their order, each read by its name.
template <class ValueOf>
std::vector<double> valuesByName(const std::vector<MethodParameter>& parameters, ValueOf value_of) {
  std::vector<double> values;
  for (const MethodParameter& p : parameters) values.push_back(value_of(p.name));
  return values;
}

[[noreturn]] inline double noSuchField(const std::string& name) {
  throw std::logic_error("no settings field for parameter " + name);
}

}  // namespace detail

inline std::optional<std::string> brokenRelation(const OctoMapParams& p) {
  if (auto e = brokenSetting(p.map)) return e;
  const auto value_of = [&](const std::string& name) {
    if (name == "p_h") return p.p_h;
    if (name == "p_m") return p.p_m;
    if (name == "p_max") return p.p_max;
    if (name == "p_min") return p.p_min;
    return detail::noSuchField(name);
  };
  const std::vector<MethodParameter> parameters = builtin::octomapParameters();
  if (auto e = brokenRelation(parameters, builtin::octomapRelations(), detail::valuesByName(parameters, value_of)))
    return e;
  return brokenThreshold(p.p_t, p.p_min, p.p_max);
}

}  // namespace occsweep
