// Where this occsweep's own files are: found from the running binary, never from the source tree, so an installed
// occsweep and one in a build folder find theirs the same way.
#pragma once

#include <filesystem>

namespace occsweep::cli {

/// The running occsweep binary (/proc/self/exe); "occsweep" (looked up on PATH) when that cannot be read.
[[nodiscard]] std::filesystem::path runningBinary();

/// <folder of the running binary>/../share/occsweep: PREFIX/share/occsweep when installed as PREFIX/bin/occsweep,
/// BUILD/share/occsweep in a build folder (the binary is BUILD/tools/occsweep). It holds plot_reproduction.py.
/// Throws std::runtime_error naming the folder when it does not exist.
[[nodiscard]] std::filesystem::path installedDataDir();

}  // namespace occsweep::cli
