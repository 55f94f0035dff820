// Where the command finds the files it ships (docs/install.md): share/occsweep/ beside the folder of its own
// executable, in the installed layout (PREFIX/bin/occsweep, PREFIX/share/occsweep/) and in the build tree, which
// mirrors it (build/tools/occsweep, build/share/occsweep/). Never the source tree: no path is compiled in.
#pragma once

#include <filesystem>

namespace occsweep::cli {

/// The running occsweep binary (/proc/self/exe); "occsweep" (looked up on PATH) when that cannot be read.
[[nodiscard]] std::filesystem::path runningBinary();

/// <folder of the running binary>/../share/occsweep, whether it exists or not: grids/ and plot_reproduction.py.
[[nodiscard]] std::filesystem::path installedDataFolder();

/// installedDataFolder(), or std::runtime_error naming it when it does not exist (for the files a command needs).
[[nodiscard]] std::filesystem::path installedDataDir();

}  // namespace occsweep::cli
