// Usage errors: which command the words of argv name, the token that is wrong, and the nearest valid name.
#include "usage_errors.hpp"

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <numeric>
#include <cctype>

#include "occsweep/io/control_characters.hpp"
#include "option_checks.hpp"

namespace occsweep::cli {
namespace {

constexpr std::size_t kNoSuggestion = std::size_t(-1);

/// The closest of `names` to `typo`, when close enough to be a typo (at most a third of the name, at least 2 edits).
std::string nearest(const std::string& typo, const std::vector<std::string>& names) {
  std::string best;
  std::size_t best_distance = kNoSuggestion;
  for (const auto& n : names) {
    const auto d = editDistance(typo, n);
    if (d < best_distance) best_distance = d, best = n;
  }
  const std::size_t allowed = std::max<std::size_t>(2, typo.size() / 3);
  return best_distance <= allowed ? best : std::string();
}

std::string didYouMean(const std::string& suggestion) {
  return suggestion.empty() ? std::string() : ": did you mean " + suggestion + "?";
}

std::vector<std::string> subcommandNames(const CLI::App& app) {
  std::vector<std::string> out;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) out.push_back(sub->get_name());
  return out;
}

const CLI::App* subcommandNamed(const CLI::App& app, const std::string& name) {
  const auto found = app.get_subcommands([&](const CLI::App* s) { return s->get_name() == name; });
  return found.empty() ? nullptr : found[0];
}

/// Every spelling of the options of `app`: --long and -s.
std::vector<std::string> optionNames(const CLI::App& app) {
  std::vector<std::string> out;
  for (const CLI::Option* opt : app.get_options()) {
    for (const auto& l : opt->get_lnames()) out.push_back("--" + l);
    for (const auto& s : opt->get_snames()) out.push_back("-" + s);
  }
  return out;
}

bool isOptionToken(const std::string& token) {
  if (token.size() < 2 || token[0] != '-') return false;
  if (token == "--") return false;
  const char c = token[1] == '-' ? (token.size() > 2 ? token[2] : 'x') : token[1];
  return !(std::isdigit(static_cast<unsigned char>(c)) || c == '.');  // -1, -0.5: negative numbers are values
}

struct Diagnosis {
  const CLI::App* command;  ///< the deepest command named on the line
  std::string path;         ///< "occsweep import cloud"
  std::string message;      ///< empty: the parse error's own message is the diagnosis
};

/// Walks the command words of argv; an unknown word where a subcommand is expected, or an option the command does
/// not have, is the diagnosis.
Diagnosis diagnose(const CLI::App& app, int argc, char** argv) {
  Diagnosis d{&app, "occsweep", ""};
  int i = 1;
  for (; i < argc; ++i) {
    const std::string word = argv[i];
    const auto names = subcommandNames(*d.command);
    if (names.empty() || isOptionToken(word)) break;
    const CLI::App* sub = subcommandNamed(*d.command, word);
    if (!sub) {
      d.message = "unknown command '" + word + "'" + didYouMean(nearest(word, names));
      if (d.message.back() != '?') d.message += " (commands: " + CLI::detail::join(names, ", ") + ")";
      return d;
    }
    d.command = sub;
    d.path += " " + word;
  }
  const auto known = optionNames(*d.command);
  for (; i < argc; ++i) {
    const std::string token = argv[i];
    if (token == "--") break;
    if (!isOptionToken(token)) continue;
    const std::string name = token.substr(0, token.find('='));
    if (const CLI::Option* option = d.command->get_option_no_throw(name)) {
      // The words it takes are its values whatever they look like (`--auc-tolerance -inf`), as CLI11 reads them.
      if (name == token) i += std::min(option->get_type_size_min(), option->get_items_expected_min());
      continue;
    }
    d.message = "unknown option " + name + didYouMean(nearest(name, known));
    return d;
  }
  return d;
}

/// CLI11's own message, reworded where it is unclear: "--k: must be ..." -> "--k must be ..." (and "--out: needs
/// ..."); a missing subcommand lists the choices.
std::string reworded(const CLI::App& command, const CLI::ParseError& error) {
  std::string text = error.what();
  if (dynamic_cast<const CLI::ValidationError*>(&error)) {
    auto colon = text.find(": must be ");
    if (colon == std::string::npos) colon = text.find(": needs ");
    if (colon != std::string::npos) text.erase(colon, 1);
  }
  if (text.rfind("A subcommand is required", 0) == 0 || text.rfind("Requires at least", 0) == 0)
    text = "a command is required: one of " + CLI::detail::join(subcommandNames(command), ", ");
  if (text.rfind("Could not convert: ", 0) == 0) {  // "Could not convert: --seed = abc"
    const std::string rest = text.substr(19);
    const auto eq = rest.find(" = ");
    if (eq != std::string::npos) text = rest.substr(0, eq) + " cannot take the value " + rest.substr(eq + 3);
  }
  return text;
}

}  // namespace

std::size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  std::iota(row.begin(), row.end(), std::size_t(0));
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

void refuseEmptyPaths(CLI::App& app) {
  const CLI::Validator non_empty(
      [](std::string& path) {
        return path.empty() ? "needs a path, got an empty value (an unset shell variable?)" : "";
      },
      "");
  for (CLI::Option* option : app.get_options())
    if (option->get_type_name() == kPath) option->check(non_empty);
  for (CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) refuseEmptyPaths(*sub);
}

int reportParseError(CLI::App& app, const CLI::ParseError& error, int argc, char** argv) {
  if (error.get_exit_code() == 0) return app.exit(error);  // --help, --version
  const Diagnosis d = diagnose(app, argc, argv);
  const std::string message = d.message.empty() ? reworded(*d.command, error) : d.message;
  std::cerr << d.path << ": error: " << escapedControlCharacters(message) << '\n'
            << "Run '" << d.path << " --help' for the options.\n";
  return 2;
}

std::string outOfMemoryMessage(const std::string& command, int argc, char** argv) {
  std::string inputs, raised;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    std::error_code ec;
    if (a.rfind("--max-", 0) == 0) raised += (raised.empty() ? "" : ", ") + a.substr(0, a.find('='));
    else if (a.rfind("-", 0) != 0 && std::filesystem::exists(a, ec)) inputs += (inputs.empty() ? "" : ", ") + a;
  }
  std::string m = "out of memory while running `occsweep " + command + "`" +
                  (inputs.empty() ? std::string() : " on " + inputs) + ": ";
  if (!raised.empty()) return m + "lower the limit you raised (" + raised + "), or use a smaller input";
  return m + "no limit was raised, so the input needs more memory than this machine gives within the default "
             "limits of docs/robustness.md; use a smaller input (for sweeps and results, a store: --out NAME.db)";
}

}  // namespace occsweep::cli
