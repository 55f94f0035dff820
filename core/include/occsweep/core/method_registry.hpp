// The registered methods by name (docs/methods.md): the ones occsweep ships, and any a program adds before it
// sweeps (examples/occupancy_method: a method of its own, registered from outside the library).
#pragma once

#include <algorithm>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "builtin_methods.hpp"
#include "mapping_method.hpp"

namespace occsweep {

/// Adds a method. Throws std::invalid_argument naming the rule broken: a name taken, empty or not of
/// [a-z0-9-], no p_max or p_min, a relation naming an unknown parameter, a parameter listed twice, a parameter
/// name not of [a-z][a-z0-9_]* or one of the settings every map shares (isReservedParameterName).
void registerMethod(std::shared_ptr<const MappingMethod> method);
/// The method of that name; std::invalid_argument naming it and every registered name when there is none.
[[nodiscard]] const MappingMethod& findMethod(const std::string& name);
/// Every registered method, by name.
[[nodiscard]] std::vector<std::shared_ptr<const MappingMethod>> registeredMethods();
/// "knn, octomap, ..." for refusals.
[[nodiscard]] std::string registeredMethodNames();

// ---------------------------------------------------------------------------------------------------------
/// Names no parameter may take: p_t (implied), the settings every map shares (resolution, s_c, variant, stats,
/// truth) and the other flags of `occsweep map`, which makes `--NAME` of each parameter (docs/methods.md, "One map").
[[nodiscard]] bool isReservedParameterName(const std::string& name);

namespace detail {

// The shipped methods are in from the start, so a lookup never races with their registration.
struct MethodTable {
  std::mutex mutex;
  std::map<std::string, std::shared_ptr<const MappingMethod>> methods;
  MethodTable();
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
                                  " and none of p_t, the map settings or `occsweep map`'s flags");
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

inline MethodTable::MethodTable() {
  addLocked(*this, std::make_shared<OctoMapMethod>());
  addLocked(*this, std::make_shared<KnnMethod>());
  addLocked(*this, std::make_shared<SorOctoMapMethod>());
  addLocked(*this, std::make_shared<RorOctoMapMethod>());
  addLocked(*this, std::make_shared<RangeOctoMapMethod>());
}

inline MethodTable& methodTable() {
  static MethodTable table;
  return table;
}

}  // namespace detail

inline bool isReservedParameterName(const std::string& name) {
  static const std::set<std::string> reserved = {"p_t",   "truth",     "dataset", "out",  "force",
                                                 "method", "from",     "best",    "map_index", "threads", "help"};
  const bool setting = std::find(kMapSettingNames.begin(), kMapSettingNames.end(), name) != kMapSettingNames.end();
  return setting || reserved.count(name) > 0 || name.rfind("max_", 0) == 0;
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
