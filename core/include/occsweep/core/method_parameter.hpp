// A method's parameters as data (docs/methods.md): each one's name, default and bounds, and the relations that must
// hold among the values of one map, as Eq. 12 states them for OctoMap and k-NN. One check reads them all.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "decimal_text.hpp"

namespace occsweep {

/// One parameter of a method, as grid files and results name it.
struct MethodParameter {
  std::string name;              ///< key in grid files and results ("p_h", "std_mul")
  std::string symbol;            ///< as docs/methods.md writes it ("p'_m")
  std::string meaning;           ///< one line for `occsweep methods`
  double default_value = 0.0;    ///< what `occsweep map` and the docs use unless told otherwise
  double lowest = 0.0, highest = 1.0;  ///< the values it may take
  bool lowest_open = false, highest_open = false;  ///< whether `lowest`, `highest` themselves are refused
  bool integer = false;          ///< a list of integers in grid files (as k), not a min/max/step range
  std::string bound_source;      ///< why the bounds hold ("Eq. 12", "l(p(s)) finite")
};

/// `larger >= smaller` (or `>` when strict) must hold among the values of one map, as Eq. 12's p_u >= p_l.
struct ParameterRelation {
  std::string larger, smaller;
  bool strict = false;
  std::string source;  ///< "Eq. 12"
};

/// True when `value` lies within `p`'s bounds (and is an integer where `p` takes integers).
[[nodiscard]] bool admits(const MethodParameter& p, double value);

/// `p`'s bounds as an interval with their source: "[0.5, 1) (Eq. 12)", "[1, 100000], an integer (Section 3.1)".
[[nodiscard]] std::string boundText(const MethodParameter& p);

/// The first bound or relation that `values` (one per parameter, in their order) break, as a sentence naming the
/// parameters by their symbols; none if every one holds.
[[nodiscard]] std::optional<std::string> brokenRelation(const std::vector<MethodParameter>& parameters,
                                                        const std::vector<ParameterRelation>& relations,
                                                        const std::vector<double>& values);

/// The index of parameter `name` in `parameters`; none when there is no such parameter.
[[nodiscard]] std::optional<std::size_t> findParameter(const std::vector<MethodParameter>& parameters,
                                                       const std::string& name);

/// Eq. 12's p_max >= p_t >= p_min, the relations of the threshold a map is classified at (p_t is no parameter of a
/// method: grids step it from each map's p_min to its p_max); none if both hold.
[[nodiscard]] std::optional<std::string> brokenThreshold(double p_t, double p_min, double p_max);

// ---------------------------------------------------------------------------------------------------------

inline bool admits(const MethodParameter& p, double value) {
  const bool low_ok = p.lowest_open ? value > p.lowest : value >= p.lowest;
  const bool high_ok = p.highest_open ? value < p.highest : value <= p.highest;
  return low_ok && high_ok && (!p.integer || value == double(static_cast<long long>(value)));
}

inline std::string boundText(const MethodParameter& p) {
  using detail::fmt;
  std::string text = p.lowest_open ? "(" : "[";  // appended, never prepended: g++ 12 warns (-Wrestrict) on "(" + s
  text += fmt(p.lowest) + ", " + fmt(p.highest) + (p.highest_open ? ")" : "]");
  return text + (p.integer ? ", an integer" : "") + " (" + p.bound_source + ")";
}

inline std::optional<std::size_t> findParameter(const std::vector<MethodParameter>& parameters,
                                                const std::string& name) {
  for (std::size_t i = 0; i < parameters.size(); ++i)
    if (parameters[i].name == name) return i;
  return std::nullopt;
}

inline std::optional<std::string> brokenRelation(const std::vector<MethodParameter>& parameters,
                                                 const std::vector<ParameterRelation>& relations,
                                                 const std::vector<double>& values) {
  using detail::fmt;
  for (std::size_t i = 0; i < parameters.size() && i < values.size(); ++i)
    if (!admits(parameters[i], values[i]))
      return parameters[i].symbol + " = " + fmt(values[i]) + " must lie in " + boundText(parameters[i]);
  for (const ParameterRelation& r : relations) {
    const std::optional<std::size_t> larger = findParameter(parameters, r.larger);
    const std::optional<std::size_t> smaller = findParameter(parameters, r.smaller);
    if (!larger || !smaller || *larger >= values.size() || *smaller >= values.size())
      return "relation " + r.larger + " >= " + r.smaller + " names a parameter the method does not have";
    const double a = values[*larger], b = values[*smaller];
    if (r.strict ? a > b : a >= b) continue;
    const std::string& big = parameters[*larger].symbol;
    const std::string& small = parameters[*smaller].symbol;
    return "parameters break " + r.source + ": " + big + (r.strict ? " > " : " >= ") + small + " does not hold (" +
           big + " = " + fmt(a) + ", " + small + " = " + fmt(b) + ")";
  }
  return std::nullopt;
}

inline std::optional<std::string> brokenThreshold(double p_t, double p_min, double p_max) {
  using detail::fmt;
  if (!(p_max >= p_t))
    return "parameters break Eq. 12: p_max >= p_t does not hold (p_max = " + fmt(p_max) + ", p_t = " + fmt(p_t) + ")";
  if (!(p_t >= p_min))
    return "parameters break Eq. 12: p_t >= p_min does not hold (p_t = " + fmt(p_t) + ", p_min = " + fmt(p_min) + ")";
  return std::nullopt;
}

}  // namespace occsweep
