// The command tree as `--help` shows it: every leaf command, its flags and its example (docs/cli.md). Shared by the
// tests of the command line's dialect and of its examples.
#pragma once

#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "test_helpers.hpp"

namespace occsweep::test {

struct LeafHelp {
  std::set<std::string> flags;          ///< long flags, --help left out
  std::vector<std::string> example;     ///< the example's commands, each starting `occsweep `
};

/// Every leaf below `command` (a command with no subcommands) and its help: option lines are indented by two spaces,
/// descriptions by more; example lines follow "Example:".
inline void walkHelp(const std::string& command, std::map<std::string, LeafHelp>& leaves) {
  const std::string help = runCli(command + " --help").output;
  const std::regex subcommand("^  ([a-z][a-z-]*)\\s.*"), option("^  (?:-[a-zA-Z],)?(--[a-z0-9-]+).*");
  std::vector<std::string> subs;
  std::istringstream in(help);
  std::string section;
  LeafHelp leaf;
  for (std::string line; std::getline(in, line);) {
    if (!line.empty() && line.back() == ':' && line[0] != ' ') section = line;
    std::smatch m;
    if (section == "Subcommands:" && std::regex_match(line, m, subcommand)) subs.push_back(m[1]);
    else if (section == "Example:" && line.starts_with("  occsweep ")) leaf.example.push_back(line.substr(2));
    else if (std::regex_match(line, m, option) && m[1] != "--help") leaf.flags.insert(m[1]);
  }
  for (const auto& sub : subs) walkHelp(command.empty() ? sub : command + " " + sub, leaves);
  if (subs.empty() && !command.empty()) leaves[command] = leaf;
}

}  // namespace occsweep::test
