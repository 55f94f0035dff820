// Usage errors (unknown command or option, a refused value, a missing option) reported like every other error:
// "occsweep CMD: error: ...", the nearest valid name for a typo, exit 2 (docs/robustness.md, "Messages, formats and
// the cluster"). --help and --version keep CLI11's output and exit 0.
#pragma once

#include <CLI/CLI.hpp>

namespace occsweep::cli {

/// Levenshtein distance between two names (for "did you mean").
[[nodiscard]] std::size_t editDistance(const std::string& a, const std::string& b);

/// Adds to every option and positional of `app` and its subcommands that takes a path (value name kPath,
/// option_checks.hpp) a check that refuses an empty one (`--out "$UNSET"`): "--out needs a path, got an empty value".
/// It runs as CLI11 reads the line, before anything is read or written, exit 2 (docs/robustness.md, "Messages,
/// formats and the cluster"). Call once every option is added.
void refuseEmptyPaths(CLI::App& app);

/// Prints the error of a failed parse of `argv` by `app` and returns the exit code: 0 for --help/--version, else 2.
int reportParseError(CLI::App& app, const CLI::ParseError& error, int argc, char** argv);

/// What `occsweep COMMAND` says when it runs out of memory: the inputs it was given (the arguments that name a file
/// or folder), and the limit flags (--max-*) raised on this command line, or that none was, so that the advice
/// never blames a flag the user did not give (docs/robustness.md, "Limits and non-regular files").
[[nodiscard]] std::string outOfMemoryMessage(const std::string& command, int argc, char** argv);

}  // namespace occsweep::cli
