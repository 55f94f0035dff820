// The figure scripts and their Python (figure_script.hpp).
#include "figure_script.hpp"

#include <cstdlib>
#include <stdexcept>
#include <vector>

#include "install_paths.hpp"
#include "occsweep/io/child_process.hpp"

namespace occsweep::cli {

std::string findPython(const std::string& configured, const std::string& command) {
  std::vector<std::string> candidates;
  if (!configured.empty()) candidates.push_back(configured);
  if (const char* env = std::getenv("OCCSWEEP_PYTHON")) candidates.emplace_back(env);
  candidates.insert(candidates.end(), {"/usr/bin/python3", "python3"});
  for (const auto& p : candidates)
    if (runCapture({p, "-c", "import matplotlib, numpy"}, true).exit_code == 0) return p;
  throw std::runtime_error(command + ": no Python 3 with matplotlib and numpy (tried " +
                           (configured.empty() ? std::string() : configured + ", ") +
                           "$OCCSWEEP_PYTHON, /usr/bin/python3, python3); install python3-matplotlib "
                           "(apt-get install python3-matplotlib) or pass --python");
}

std::filesystem::path figureScript(const std::string& name) {
  const std::filesystem::path script = installedDataDir() / name;
  if (!std::filesystem::is_regular_file(script)) throw std::runtime_error(script.string() + ": not found (the figure script)");
  return script;
}

}  // namespace occsweep::cli
