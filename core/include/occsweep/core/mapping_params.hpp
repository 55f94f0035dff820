// The settings of the two mappers the paper compares (octomap_baseline.hpp, knn_inverse_sensor_model.hpp): their
// parameters' values, whose defaults and checks come from the parameters' one home (builtin_parameters.hpp), and the
// settings every map shares (map_settings.hpp). OctoMapMethod and KnnMethod fill these from a map's values.
#pragma once

#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "builtin_parameters.hpp"
#include "map_settings.hpp"

namespace occsweep {

namespace detail {
[[nodiscard]] double octomapDefault(const std::string& name);
[[nodiscard]] double knnDefault(const std::string& name);
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

/// Parameters of the k-NN inverse sensor model (Eq. 6-10, Algorithm 1).
struct KnnParams {
  double p_u = detail::knnDefault("p_u");          ///< upper bound of p(s) (Eq. 6): a point with tight neighbours
  double p_l = detail::knnDefault("p_l");          ///< lower bound of p(s) (Eq. 6): an isolated point
  double p_m = detail::knnDefault("p_m");          ///< miss for voxels crossed by rays to in-range points (l_in)
  double p_m_out = detail::knnDefault("p_m_out");  ///< p'_m: miss for voxels crossed only by rays beyond s_c (l_out)
  double p_max = detail::knnDefault("p_max");      ///< upper clamping threshold
  double p_min = detail::knnDefault("p_min");      ///< lower clamping threshold
  double p_t = 0.5;                                ///< occupancy threshold
  int k = static_cast<int>(detail::knnDefault("k"));  ///< number of nearest neighbours averaged (Section 3.1)
  MapSettings map;
};

/// The first setting, bound or relation of Eq. 12 the parameters break, as a sentence naming it; none if valid.
[[nodiscard]] std::optional<std::string> brokenRelation(const OctoMapParams& p);
[[nodiscard]] std::optional<std::string> brokenRelation(const KnnParams& p);

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

inline double knnDefault(const std::string& name) {
  static const std::vector<MethodParameter> parameters = builtin::knnParameters();
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
  throw std::logic_error("mapping_params.hpp: no field for parameter " + name);
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

inline std::optional<std::string> brokenRelation(const KnnParams& p) {
  if (auto e = brokenSetting(p.map)) return e;
  const auto value_of = [&](const std::string& name) {
    if (name == "k") return double(p.k);
    if (name == "p_u") return p.p_u;
    if (name == "p_l") return p.p_l;
    if (name == "p_m") return p.p_m;
    if (name == "p_m_out") return p.p_m_out;
    if (name == "p_max") return p.p_max;
    if (name == "p_min") return p.p_min;
    return detail::noSuchField(name);
  };
  const std::vector<MethodParameter> parameters = builtin::knnParameters();
  if (auto e = brokenRelation(parameters, builtin::knnRelations(), detail::valuesByName(parameters, value_of)))
    return e;
  return brokenThreshold(p.p_t, p.p_min, p.p_max);
}

}  // namespace occsweep
