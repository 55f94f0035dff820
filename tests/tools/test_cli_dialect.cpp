// One flag name per concept (docs/cli.md): every leaf command's flags, read from its --help, against the table of
// docs/cli.md, and no second spelling of a concept anywhere.
#include <catch2/catch.hpp>

#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>

#include "cli_help.hpp"
#include "test_paths.hpp"

namespace {

using Flags = std::map<std::string, std::set<std::string>>;  // flag -> leaf commands that take it

std::string docsCli() {
  std::ifstream in(occsweep::test::sourceTree().string() + "/docs/cli.md");
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// The text between `<!-- NAME ... -->` and `<!-- end of NAME -->` in docs/cli.md.
std::string block(const std::string& doc, const std::string& name) {
  const auto begin = doc.find("<!-- " + name), end = doc.find("<!-- end of " + name);
  REQUIRE(begin != std::string::npos);
  REQUIRE(end != std::string::npos);
  return doc.substr(begin, end - begin);
}

// The table's rows: | `--flag` | command, command | concept |
Flags documentedFlags(const std::string& doc) {
  Flags flags;
  std::istringstream in(block(doc, "flag table"));
  const std::regex row("^\\| `(--[a-z0-9-]+)` \\| ([^|]+) \\|.*");
  for (std::string line; std::getline(in, line);) {
    std::smatch m;
    if (!std::regex_match(line, m, row)) continue;
    std::istringstream commands(m[2].str());
    for (std::string c; std::getline(commands, c, ',');) {
      c.erase(0, c.find_first_not_of(' '));
      c.erase(c.find_last_not_of(' ') + 1);
      flags[m[1]].insert(c);
    }
  }
  return flags;
}

}  // namespace

TEST_CASE("every leaf command's flags are the ones docs/cli.md lists for it, and no concept has a second spelling") {
  std::map<std::string, occsweep::test::LeafHelp> leaves;
  occsweep::test::walkHelp("", leaves);
  Flags flags;
  for (const auto& [command, help] : leaves)
    for (const auto& flag : help.flags) flags[flag].insert(command);
  CHECK(leaves.size() >= 30);
  CHECK(leaves.count("sweep"));
  CHECK(leaves.count("cluster run-local"));
  const std::string doc = docsCli();
  const Flags documented = documentedFlags(doc);
  for (const auto& [flag, commands] : flags) {
    INFO(flag);
    CHECK(documented.count(flag));
    if (documented.count(flag)) CHECK(documented.at(flag) == commands);
  }
  for (const auto& [flag, commands] : documented) {
    INFO(flag << " is in docs/cli.md but no command takes it");
    CHECK(flags.count(flag));
  }
  // The refused spellings: none is a flag of any command.
  std::istringstream refused(block(doc, "refused spellings"));
  std::size_t spellings = 0;
  for (std::string word; refused >> word;) {
    if (!word.starts_with("`--")) continue;
    const std::string flag = word.substr(1, word.size() - 2);
    ++spellings;
    INFO(flag << " is a second spelling of a concept (docs/cli.md)");
    CHECK_FALSE(flags.count(flag));
  }
  CHECK(spellings >= 10);
}
