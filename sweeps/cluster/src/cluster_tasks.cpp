// Rendering a cluster task's argv from its typed description (cluster_tasks.hpp); the commands' option
// registrations (tools/occsweep/task_options.cpp) are the inverse.
#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include "occsweep/sweeps/cluster_tasks.hpp"

namespace occsweep {
namespace {

/// A value the parser reads back as itself: not empty, not starting with '-'.
const std::string& value(const std::string& v, const char* what) {
  if (v.empty() || v[0] == '-')
    throw std::invalid_argument(std::string(what) + " '" + v + "': a task's argument must be non-empty and not start "
                                "with '-' (the command would read it as an option)");
  return v;
}

/// The shortest text that the command's parser (CLI11: strtold, then double) reads back as exactly `x`; 17
/// significant digits when the shortest one does not survive that double rounding.
std::string exactNumber(double x) {
  char buf[64];
  const auto end = std::to_chars(buf, buf + sizeof buf, x).ptr;
  std::string text(buf, end);
  if (static_cast<double>(std::strtold(text.c_str(), nullptr)) != x) {
    std::snprintf(buf, sizeof buf, "%.17g", x);
    text = buf;
  }
  return text;
}

std::string fraction(std::uint64_t i, std::uint64_t n) { return std::to_string(i) + "/" + std::to_string(n); }

void addFiles(std::vector<std::string>& argv, const std::vector<std::string>& files, const char* what) {
  if (files.empty()) throw std::invalid_argument(std::string(what) + ": no files");
  for (const auto& f : files) argv.push_back(value(f, what));
}

}  // namespace

std::vector<std::string> taskArgv(const SweepConfig& s) {
  if (!s.observable_out.empty()) throw std::invalid_argument("sweep task: observable_out has no command-line option");
  const SweepConfig defaults;
  std::vector<std::string> argv = {"sweep", "--dataset", value(s.dataset.string(), "--dataset"),
                                   "--grid", value(s.grid, "--grid"), "--out", value(s.out.string(), "--out"),
                                   "--shard", fraction(s.selection.shard_index, s.selection.shard_count),
                                   "--threads", std::to_string(s.threads)};
  auto add = [&argv](const char* flag, const std::string& v) { argv.insert(argv.end(), {flag, value(v, flag)}); };
  if (const auto& g = s.selection.group) {
    add("--group", fraction(g->index, g->count));
    add("--seed", std::to_string(g->seed));
  }
  if (s.map.resolution != defaults.map.resolution) add("--resolution", exactNumber(s.map.resolution));
  if (s.map.s_c != defaults.map.s_c) add("--s-c", exactNumber(s.map.s_c));
  if (s.map.variant != defaults.map.variant) add("--variant", toText(s.map.variant));
  if (s.map.stats != defaults.map.stats) add("--stats", toText(s.map.stats));
  if (s.engine != defaults.engine) add("--engine", s.engine);
  if (s.truth != defaults.truth) add("--truth", truthModeName(s.truth));
  if (s.quiet) argv.push_back("--quiet");
  if (s.force) argv.push_back("--force");
  return argv;
}

std::vector<std::string> taskArgv(const MergeTask& m) {
  std::vector<std::string> argv = {"merge"};
  addFiles(argv, m.files, "merge");
  argv.insert(argv.end(), {"--out", value(m.out, "--out")});
  if (m.force) argv.push_back("--force");
  return argv;
}

std::vector<std::string> taskArgv(const CompareTask& c) {
  std::vector<std::string> argv = {"compare"};
  addFiles(argv, c.files, "compare");
  if (c.force) argv.push_back("--force");
  if (!c.json.empty()) argv.insert(argv.end(), {"--json", value(c.json, "--json")});
  if (c.allow_mixed) argv.push_back("--allow-mixed");
  if (c.baseline != CompareTask{}.baseline) argv.insert(argv.end(), {"--baseline", value(c.baseline, "--baseline")});
  if (!c.csv.empty()) argv.insert(argv.end(), {"--csv", value(c.csv, "--csv")});
  if (!c.markdown.empty()) argv.insert(argv.end(), {"--markdown", value(c.markdown, "--markdown")});
  if (!c.latex.empty()) argv.insert(argv.end(), {"--latex", value(c.latex, "--latex")});
  if (c.alpha != CompareTask{}.alpha) argv.insert(argv.end(), {"--alpha", exactNumber(c.alpha)});
  if (c.smallest_effect != CompareTask{}.smallest_effect)
    argv.insert(argv.end(), {"--smallest-effect", exactNumber(c.smallest_effect)});
  if (c.units != CompareTask{}.units) argv.insert(argv.end(), {"--units", value(c.units, "--units")});
  return argv;
}

std::vector<std::string> taskArgv(const SelectTask& s) {
  std::vector<std::string> argv = {"cluster", "select", "--out", value(s.out, "--out")};
  addFiles(argv, s.rankings, "cluster select");
  return argv;
}

}  // namespace occsweep
