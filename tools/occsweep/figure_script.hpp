// The project's matplotlib scripts (share/occsweep beside the binary: docs/install.md) and the Python that runs them.
#pragma once

#include <filesystem>
#include <string>

namespace occsweep::cli {

/// A Python 3 that imports matplotlib and numpy: `configured` if given, else $OCCSWEEP_PYTHON, /usr/bin/python3,
/// python3. Throws std::runtime_error naming `command` and saying what to install when none does.
[[nodiscard]] std::string findPython(const std::string& configured, const std::string& command);

/// The installed script of that name; std::runtime_error when it is not there.
[[nodiscard]] std::filesystem::path figureScript(const std::string& name);

}  // namespace occsweep::cli
