// The occsweep command line as a function: the occsweep program is this alone; a program that registers methods
// of its own first (registerMethod) gets the same commands for them (docs/methods.md, "Bring your own method").
#pragma once

namespace occsweep::cli {

/// Parses `argv` against every registered subcommand and runs the one named: its exit code, 2 for a usage or
/// input error (reported on stderr). Call once per process: it installs the SIGINT/SIGTERM and SIGPIPE handling.
int runCommandLine(int argc, char** argv);

}  // namespace occsweep::cli
