// The k-NN inverse sensor model's parameters as data (names, defaults as in the paper's Table 1, bounds and Eq. 12's
// relations, written once) and the settings of its mapper, which take their defaults and checks from them. The
// clamping and in-range miss parameters are OctoMap's (octomap_parameters.hpp).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "occsweep/methods/octomap/octomap_parameters.hpp"

namespace occsweep::builtin {

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

}  // namespace occsweep::builtin

namespace occsweep {

namespace detail {
[[nodiscard]] double knnDefault(const std::string& name);
}  // namespace detail

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
[[nodiscard]] std::optional<std::string> brokenRelation(const KnnParams& p);

// ---------------------------------------------------------------------------------------------------------

inline double detail::knnDefault(const std::string& name) {
  static const std::vector<MethodParameter> parameters = builtin::knnParameters();
  return builtin::defaultOf(parameters, name);
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
