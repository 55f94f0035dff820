// The truth-coverage line and its warnings, as `import truth` and `sweep` print them (docs/import.md, "Truth
// coverage and alignment"); `compare` gives the warnings as notes.
#pragma once

#include <iostream>
#include <string>

#include "occsweep/io/control_characters.hpp"
#include "occsweep/eval/truth_coverage.hpp"

namespace occsweep::cli {

/// The coverage on stdout, its warning (if any) on stderr after "`command`: warning: `dataset`: ".
inline void reportCoverage(const TruthCoverage& c, TruthMode mode, const std::string& command,
                           const std::string& dataset) {
  std::cout << coverageText(c) << '\n';
  if (const std::string w = coverageWarning(c, mode); !w.empty())
    std::cerr << command << ": warning: " << escapedControlCharacters(dataset) << ": " << w << '\n';
}

}  // namespace occsweep::cli
