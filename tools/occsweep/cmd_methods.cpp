// occsweep methods: every registered method with its parameters and a one-line description (docs/methods.md).
#include <cstdio>
#include <iostream>

#include "command_registry.hpp"
#include "occsweep/core/method_registry.hpp"

namespace occsweep::cli {
namespace {

// "[0.5, 1)" from a parameter's bounds, ", integer" for listed integers.
std::string boundsText(const MethodParameter& p) {
  return std::string(p.lowest_open ? "(" : "[") + detail::fmt(p.lowest) + ", " + detail::fmt(p.highest) +
         (p.highest_open ? ")" : "]") + (p.integer ? " integer" : "");
}

void printMethod(const MappingMethod& m) {
  std::cout << m.name() << ": " << m.description() << "\n  reference: " << m.reference() << '\n';
  for (const MethodParameter& p : m.parameters())
    std::printf("  %-14s %-6s default %-8s %-20s %s\n", p.name.c_str(), p.symbol.c_str(),
                detail::fmt(p.default_value).c_str(), boundsText(p).c_str(), p.meaning.c_str());
  std::string relations;
  for (const ParameterRelation& r : m.relations())
    relations += (relations.empty() ? "" : ", ") + r.larger + (r.strict ? " > " : " >= ") + r.smaller;
  if (!relations.empty()) std::cout << "  relations: " << relations << '\n';
  std::cout << "  and p_t from p_min to p_max (every method)\n";
}

const RegisterCommand kMethods{"methods", "List every registered mapping method with its parameters (docs/methods.md)",
                               [](CLI::App& app) {
  addExample(app, "occsweep methods");
  return [] {
    for (const auto& m : registeredMethods()) printMethod(*m);
    return 0;
  };
}};

}  // namespace
}  // namespace occsweep::cli
