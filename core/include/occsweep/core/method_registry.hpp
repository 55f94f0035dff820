// The registered methods by name (docs/methods.md): a program registers occsweep's own (the methods layer does it for
// the command) and any of its own before it sweeps (examples/occupancy_method). The registry knows none of them.
#pragma once

#include <algorithm>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

#include "mapping_method.hpp"

namespace occsweep {

/// Adds a method. Throws std::invalid_argument naming the rule broken: a name taken, empty or not of
/// [a-z0-9-], no p_max or p_min, a relation naming an unknown parameter, a parameter listed twice, a parameter
/// name not of [a-z][a-z0-9_]* or one of the names every map has (isReservedParameterName).
void registerMethod(std::shared_ptr<const MappingMethod> method);
/// The method of that name; std::invalid_argument naming it and every registered name when there is none.
[[nodiscard]] const MappingMethod& findMethod(const std::string& name);
/// Every registered method, by name.
[[nodiscard]] std::vector<std::shared_ptr<const MappingMethod>> registeredMethods();
/// Every registered name, comma-separated, for refusals.
[[nodiscard]] std::string registeredMethodNames();

// ---------------------------------------------------------------------------------------------------------
/// Names no parameter may take: p_t (every map's, stepped by grids) and the settings every map shares (resolution,
/// s_c, variant, stats), which results files key beside the parameters (docs/methods.md, "One map").
[[nodiscard]] bool isReservedParameterName(const std::string& name);

namespace detail {

struct MethodTable {
  std::mutex mutex;
  std::map<std::string, std::shared_ptr<const MappingMethod>> methods;
};

inline bool isParameterName(const std::string& name) {
  return !name.empty() && name[0] >= 'a' && name[0] <= 'z' &&
         name.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789_") == std::string::npos;
}

inline void checkMethod(const MappingMethod& m) {
  const std::string name = m.name();
  if (name.empty() || name.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789-") != std::string::npos)
    throw std::invalid_argument("method '" + name + "': a name is lower-case letters, digits and '-'");
  std::map<std::string, int> seen;
  for (const MethodParameter& p : m.parameters()) {
    if (!isParameterName(p.name) || isReservedParameterName(p.name))
      throw std::invalid_argument("method " + name + ": parameter '" + p.name + "': a parameter name is [a-z][a-z0-9_]*"
                                  " and none of p_t or the map settings");
    if (++seen[p.name] > 1) throw std::invalid_argument("method " + name + ": parameter " + p.name + " listed twice");
  }
  for (const char* needed : {"p_max", "p_min"})
    if (!seen.count(needed)) throw std::invalid_argument("method " + name + ": needs a parameter " + needed);
  for (const ParameterRelation& r : m.relations())
    if (!seen.count(r.larger) || !seen.count(r.smaller))
      throw std::invalid_argument("method " + name + ": relation " + r.larger + " >= " + r.smaller +
                                  " names an unknown parameter");
  for (const std::string& shared : m.sharedByLanes())
    if (!seen.count(shared)) throw std::invalid_argument("method " + name + ": shares unknown parameter " + shared);
}

inline void addLocked(MethodTable& table, std::shared_ptr<const MappingMethod> method) {
  checkMethod(*method);
  const std::string name = method->name();
  if (!table.methods.emplace(name, std::move(method)).second)
    throw std::invalid_argument("method " + name + " is registered already");
}

inline MethodTable& methodTable() {
  static MethodTable table;
  return table;
}

}  // namespace detail

inline bool isReservedParameterName(const std::string& name) {
  return name == "p_t" || std::find(kMapSettingNames.begin(), kMapSettingNames.end(), name) != kMapSettingNames.end();
}

inline void registerMethod(std::shared_ptr<const MappingMethod> method) {
  if (!method) throw std::invalid_argument("registerMethod: no method");
  detail::MethodTable& table = detail::methodTable();
  const std::lock_guard lock(table.mutex);
  detail::addLocked(table, std::move(method));
}

inline const MappingMethod& findMethod(const std::string& name) {
  detail::MethodTable& table = detail::methodTable();
  const std::lock_guard lock(table.mutex);
  const auto it = table.methods.find(name);
  if (it != table.methods.end()) return *it->second;
  std::string names;
  for (const auto& [n, _] : table.methods) names += (names.empty() ? "" : ", ") + n;
  if (names.empty()) names = "none; a program registers methods before it looks one up";
  throw std::invalid_argument("method '" + name + "' is not registered (registered: " + names + ")");
}

inline std::vector<std::shared_ptr<const MappingMethod>> registeredMethods() {
  detail::MethodTable& table = detail::methodTable();
  const std::lock_guard lock(table.mutex);
  std::vector<std::shared_ptr<const MappingMethod>> out;
  for (const auto& [_, m] : table.methods) out.push_back(m);
  return out;
}

inline std::string registeredMethodNames() {
  std::string names;
  for (const auto& m : registeredMethods()) names += (names.empty() ? "" : ", ") + m->name();
  return names;
}

}  // namespace occsweep
