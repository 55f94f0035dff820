// The check that a committed reference header is still what its Python script prints (docs/statistics.md,
// "Reference values for the tests"): one home for the stats, correlation and verdict tests.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <string>

#include <catch2/catch.hpp>

#include "test_helpers.hpp"

namespace occsweep::test {

/// Runs tools/SCRIPT.py with /usr/bin/python3 and requires tests/SCRIPT_cases.hpp byte for byte; where
/// `python_requirement` (a Python statement, e.g. "import scipy") fails, warns that `packages` are missing and
/// skips: the committed values are then what the other tests use.
inline void requireReferenceScriptUnchanged(const std::string& script, const std::string& python_requirement,
                                            const std::string& packages) {
  const auto source = occsweep::test::sourceTree();
  if (std::system(("/usr/bin/python3 -c '" + python_requirement + "' 2>/dev/null").c_str()) != 0) {
    WARN("skipped: /usr/bin/python3 with " + packages + " is not installed (the committed values are used above)");
    return;
  }
  const auto out = scratch(script) / "cases.hpp";
  const std::string command =
      "/usr/bin/python3 " + (source / "tools" / (script + ".py")).string() + " > " + out.string();
  REQUIRE(std::system(command.c_str()) == 0);
  CHECK(bytesOf(out) == bytesOf(source / "tests" / (script + "_cases.hpp")));
}

}  // namespace occsweep::test
