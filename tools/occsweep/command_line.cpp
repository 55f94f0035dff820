// The occsweep command line (docs/cli.md): every registered subcommand, parsed and run, errors reported with exit 2.
#include "command_line.hpp"

#include <csignal>

#include <algorithm>
#include <iostream>
#include <map>
#include <new>

#include "command_registry.hpp"
#include "install_paths.hpp"
#include "occsweep/eval/output_file.hpp"
#include "occsweep/sweeps/grid.hpp"
#include "occsweep/sweeps/version.hpp"
#include "usage_errors.hpp"

namespace occsweep::cli {

namespace {

// `argv` as a shell reads it back: an argument of other than plain characters in single quotes.
std::string shellCommand(int argc, char** argv) {
  std::string line;
  for (int i = 0; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool plain = !arg.empty() && arg.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                                             "0123456789_./=:,+-@%") == std::string::npos;
    std::string quoted = "'";
    for (char ch : arg) quoted += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
    line += (i ? " " : "") + (plain ? arg : quoted + "'");
  }
  return line;
}

}  // namespace

int runCommandLine(int argc, char** argv) {
  removeTemporariesOnInterrupt();  // before any thread: SIGINT/SIGTERM remove unfinished outputs
  // A reader that goes away (`occsweep grid list | head -1`) fails a write with EPIPE instead of killing occsweep
  // mid-work by SIGPIPE: a sweep finishes and commits its results, nothing partial is left (docs/robustness.md).
  ::signal(SIGPIPE, SIG_IGN);
  addGridFolder(installedDataFolder() / "grids");  // after $OCCSWEEP_GRIDS (docs/install.md)
  CLI::App app{"occsweep " + std::string(kVersion) +
               ": occupancy mapping with OctoMap and the k-NN inverse sensor model (Miao et al., Sensors 2022)"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string(kVersion) + " (" + kGitCommit + ")");
  auto specs = commandRegistry();
  std::sort(specs.begin(), specs.end(), [](const auto& a, const auto& b) { return a.name < b.name; });
  std::map<CLI::App*, std::pair<const CommandSpec*, std::function<int()>>> runners;
  for (const auto& spec : specs) {
    CLI::App* sub = app.add_subcommand(spec.name, spec.help);
    runners[sub] = {&spec, spec.setup(*sub)};
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return reportParseError(app, e, argc, argv);
  }
  for (auto& [sub, spec_and_run] : runners) {
    if (!sub->parsed()) continue;
    const auto& [spec, run] = spec_and_run;
    if (!spec->kept_on_interrupt.empty())
      setInterruptMessage("occsweep " + spec->name + ": interrupted; " + spec->kept_on_interrupt +
                          ". The same command resumes:\n  " + shellCommand(argc, argv) + "\n");
    try {
      return run();
    } catch (const CLI::ParseError& e) {
      return e.get_exit_code() == 0 ? sub->exit(e) : reportParseError(app, e, argc, argv);
    } catch (const std::bad_alloc&) {  // never an abort; the limits should have refused the input first
      std::cerr << "occsweep " << sub->get_name() << ": error: " << outOfMemoryMessage(sub->get_name(), argc, argv)
                << '\n';
      return 2;
    } catch (const std::exception& e) {
      std::cerr << "occsweep " << sub->get_name() << ": error: " << e.what() << '\n';
      return 2;
    }
  }
  return 1;
}

}  // namespace occsweep::cli
