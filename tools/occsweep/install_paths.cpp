#include "install_paths.hpp"

#include <system_error>

namespace occsweep::cli {

std::filesystem::path executableFolder() {
  std::error_code ec;
  const auto exe = std::filesystem::canonical("/proc/self/exe", ec);
  return ec ? std::filesystem::path(".") : exe.parent_path();
}

std::filesystem::path installedDataFolder() {
  return (executableFolder() / ".." / "share" / "occsweep").lexically_normal();
}

}  // namespace occsweep::cli
