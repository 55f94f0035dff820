// `dataset middlebury`, a subcommand of `dataset` (cmd_dataset.cpp) in its own file.
#pragma once

#include <functional>
#include <utility>

#include <CLI/CLI.hpp>

namespace occsweep::cli {

/// Adds `middlebury` to the `dataset` command; returns the subcommand and what runs it.
[[nodiscard]] std::pair<CLI::App*, std::function<int()>> addDatasetMiddlebury(CLI::App& dataset);

}  // namespace occsweep::cli
