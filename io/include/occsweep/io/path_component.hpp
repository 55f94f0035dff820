// Names that become one component of a path (a grid's name, a data set's key in a plan): the one rule for them.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "occsweep/io/control_characters.hpp"

namespace occsweep {

/// The rule `name` breaks as a single, harmless path component, or none: it must not be empty, hold `/` or `\`,
/// start with `.` (so neither `.` nor `..` nor a hidden file), or hold control characters. Such names join folders
/// (`sweeps/SET/GRID/...`, `merged/SET/GRID.json`), so a name like `../../victim` would put outputs, and their
/// removal on a re-run, outside the folder they belong to (docs/cluster.md, "Outputs stay in the plan folder").
[[nodiscard]] inline std::optional<std::string> brokenPathComponentRule(std::string_view name) {
  const std::string rule = "must be a single path component (no '/' or '\\', no leading '.', no control characters), "
                           "since it names output files and folders";
  if (name.empty() || name.front() == '.' || name.find_first_of("/\\") != std::string_view::npos ||
      hasControlCharacters(name))
    return rule;
  return std::nullopt;
}

}  // namespace occsweep
