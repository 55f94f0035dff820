// The running binary and the data folder beside it (install_paths.hpp).
#include "install_paths.hpp"

#include <stdexcept>
#include <system_error>

namespace occsweep::cli {
namespace fs = std::filesystem;

fs::path runningBinary() {
  std::error_code ec;
  const fs::path p = fs::read_symlink("/proc/self/exe", ec);
  return ec ? fs::path("occsweep") : p;
}

fs::path installedDataFolder() {
  return (runningBinary().parent_path() / ".." / "share" / "occsweep").lexically_normal();
}

fs::path installedDataDir() {
  const fs::path dir = installedDataFolder();
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw std::runtime_error(dir.string() + ": not found; occsweep looks for its data files (plot_reproduction.py) "
                             "in ../share/occsweep beside its binary (install occsweep, or build it with CMake)");
  return dir;
}

}  // namespace occsweep::cli
