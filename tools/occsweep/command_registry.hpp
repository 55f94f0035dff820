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
};

inline std::vector<CommandSpec>& commandRegistry() {
  static std::vector<CommandSpec> all;
  return all;
}

struct RegisterCommand {
  RegisterCommand(std::string name, std::string help, CommandSetup setup) {
    commandRegistry().push_back({std::move(name), std::move(help), std::move(setup)});
  }
};

/// For commands with their own subcommands (`grid count`): runs the chosen one, or prints help.
inline int runChosen(const std::vector<std::pair<CLI::App*, std::function<int()>>>& subs) {
  for (const auto& [sub, run] : subs)
    if (sub->parsed()) return run();
  throw CLI::CallForHelp();
}

}  // namespace occsweep::cli
