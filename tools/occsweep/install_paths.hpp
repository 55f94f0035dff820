// Where the command finds the files it ships (docs/install.md): share/occsweep/ beside the folder of its own
// executable, in the installed layout (PREFIX/bin/occsweep, PREFIX/share/occsweep/) and in the build tree, which
// mirrors it (build/tools/occsweep, build/share/occsweep/). No path is compiled in.
#pragma once

#include <filesystem>

namespace occsweep::cli {

/// The folder of the running executable (/proc/self/exe, links resolved).
[[nodiscard]] std::filesystem::path executableFolder();

/// EXE_FOLDER/../share/occsweep: grids/ and plot_reproduction.py.
[[nodiscard]] std::filesystem::path installedDataFolder();

}  // namespace occsweep::cli
