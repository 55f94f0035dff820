// Each subcommand lives in its own file and registers itself here, so adding one touches no other file.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace occsweep::cli {

/// Adds a subcommand's options to `app` and returns what runs it (its exit code).
using CommandSetup = std::function<std::function<int()>(CLI::App& app)>;

struct CommandSpec {
  std::string name;
  std::string help;
  CommandSetup setup;
  /// For a command that resumes where an interrupt stopped it: what it keeps ("its finished maps are kept in ...").
  /// An interrupt then prints it and the exact command line that resumes (docs/cli.md, "Progress").
  std::string kept_on_interrupt = {};
};

inline std::vector<CommandSpec>& commandRegistry() {
  static std::vector<CommandSpec> all;
  return all;
}

struct RegisterCommand {
  RegisterCommand(std::string name, std::string help, CommandSetup setup, std::string kept_on_interrupt = {}) {
    commandRegistry().push_back({std::move(name), std::move(help), std::move(setup), std::move(kept_on_interrupt)});
  }
};

/// The runnable example at the end of a leaf command's --help: one command per line, each starting `occsweep `,
/// run in this order from the repository's root by tests/tools/test_help_examples.cpp.
inline void addExample(CLI::App& app, const std::string& lines) {
  std::string text = "\nExample:";
  std::size_t start = 0;
  for (std::size_t end; (end = lines.find('\n', start)) != std::string::npos; start = end + 1)
    text += "\n  " + lines.substr(start, end - start);
  if (start < lines.size()) text += "\n  " + lines.substr(start);
  app.footer(text);
}

/// For commands with their own subcommands (`grid count`): runs the chosen one, or prints help.
inline int runChosen(const std::vector<std::pair<CLI::App*, std::function<int()>>>& subs) {
  for (const auto& [sub, run] : subs)
    if (sub->parsed()) return run();
  throw CLI::CallForHelp();
}

}  // namespace occsweep::cli
