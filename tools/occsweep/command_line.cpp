// The occsweep command line (docs/cli.md): every registered subcommand, parsed and run, errors reported with exit 2.
#include "command_line.hpp"

#include <csignal>
#include <unistd.h>

#include <algorithm>
#include <exception>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <new>
#include <stdexcept>

#include "command_registry.hpp"
#include "install_paths.hpp"
#include "occsweep/io/child_process.hpp"
#include "occsweep/io/control_characters.hpp"
#include "occsweep/io/output_file.hpp"
#include "occsweep/sweeps/grid.hpp"
#include "occsweep/sweeps/version.hpp"
#include "occsweep/io/temporaries.hpp"
#include "occsweep/methods/builtin_methods.hpp"
#include "usage_errors.hpp"

namespace occsweep::cli {

namespace {

// `argv` as a shell reads it back, shown safely on a terminal (shownShellWord).
std::string shellCommand(int argc, char** argv) {
  std::string line;
  for (int i = 0; i < argc; ++i) line += (i ? " " : "") + shownShellWord(argv[i]);
  return line;
}

// What an interrupt of a command that resumes prints: what it kept, and the command in its folder (a relative path
// in it means that folder). On a terminal it starts on a line of its own, below the progress bar.
std::string resumeMessage(const CommandSpec& spec, int argc, char** argv) {
  std::error_code ec;
  const std::filesystem::path folder = std::filesystem::current_path(ec);
  return std::string(::isatty(STDERR_FILENO) ? "\n" : "") + "occsweep " + spec.name + ": interrupted; " +
         spec.kept_on_interrupt + ". The same command in the same folder resumes it:\n  " +
         (ec ? "" : "cd " + shownShellWord(folder.string()) + " && ") + shellCommand(argc, argv) + "\n";
}

// What a bad_alloc prints (outOfMemoryMessage): made before the command runs, since after one no memory may be left
// to make it.
std::string& outOfMemoryReport() {
  static std::string report;
  return report;
}

// Address space set aside at the start and given back when memory runs out, so that the exit can still allocate.
std::unique_ptr<char[]>& memoryReserve() {
  static std::unique_ptr<char[]> reserve;
  return reserve;
}

// A bad_alloc no catch reaches ends in std::terminate: thrown in a destructor (nlohmann::json's allocates to free a
// tree, so a parse that ran out of memory failed again while unwinding: exit 134), in a noexcept function or on a
// thread. It ends as one run() throws: the message, temporaries removed, exit 2. Any other exception keeps the
// default: its type printed, abort.
std::terminate_handler g_default_terminate = nullptr;
[[noreturn]] void terminateOnOutOfMemory() {
  bool out_of_memory = false;
  if (const std::exception_ptr e = std::current_exception()) {
    try {
      std::rethrow_exception(e);
    } catch (const std::bad_alloc&) {
      out_of_memory = true;
    } catch (...) {
    }
  }
  if (!out_of_memory) g_default_terminate();
  memoryReserve().reset();
  exitRemovingTemporaries(2, outOfMemoryReport());
}

}  // namespace

int runCommandLine(int argc, char** argv) {
  removeTemporariesOnInterrupt();  // before any thread: SIGINT/SIGTERM remove unfinished outputs
  memoryReserve() = std::make_unique_for_overwrite<char[]>(std::size_t(8) << 20);  // untouched: no resident memory
  g_default_terminate = std::set_terminate(terminateOnOutOfMemory);
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
  try {  // occsweep's own methods, beside any the program registered before (docs/methods.md)
    registerBuiltinMethods();
    for (const auto& spec : specs) {
      CLI::App* sub = app.add_subcommand(spec.name, spec.help);
      runners[sub] = {&spec, spec.setup(*sub)};
    }
  } catch (const std::invalid_argument& e) {  // a registered method the commands cannot take (map's flags)
    std::cerr << "occsweep: error: " << escapedControlCharacters(e.what()) << '\n';
    return 2;
  }
  refuseEmptyPaths(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return reportParseError(app, e, argc, argv);
  }
  for (auto& [sub, spec_and_run] : runners) {
    if (!sub->parsed()) continue;
    const auto& [spec, run] = spec_and_run;
    if (!spec->kept_on_interrupt.empty())
      setInterruptMessage(resumeMessage(*spec, argc, argv));
    const std::string& name = sub->get_name();
    outOfMemoryReport() = "occsweep " + name + ": error: " + outOfMemoryMessage(name, argc, argv) + '\n';
    try {
      return run();
    } catch (const CLI::ParseError& e) {
      return e.get_exit_code() == 0 ? sub->exit(e) : reportParseError(app, e, argc, argv);
    } catch (const std::bad_alloc&) {  // never an abort; the limits should have refused the input first
      std::cerr << outOfMemoryReport();
      return 2;
    } catch (const std::exception& e) {  // a name or path in it shows its control characters escaped
      std::cerr << "occsweep " << sub->get_name() << ": error: " << escapedControlCharacters(e.what()) << '\n';
      return 2;
    }
  }
  return 1;
}

}  // namespace occsweep::cli
