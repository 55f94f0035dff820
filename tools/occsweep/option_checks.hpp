// Checks of numeric command-line values, shared by every command: a refused value is reported with the rule in plain
// numbers ("--threads must be an integer >= 0, got -1"), never with CLI11's defaults (a 309-digit double maximum), see
// docs/robustness.md, "Messages, formats and the cluster". main.cpp turns "--k: must ..." into "--k must ...".
#pragma once

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>
#include <type_traits>

#include <CLI/CLI.hpp>

#include "occsweep/io/control_characters.hpp"

namespace occsweep::cli {

/// The value name of an option that takes a file or a folder (`--out PATH` in --help): an empty value is refused
/// as one that "needs a path" (refuseEmptyPaths, usage_errors.hpp).
inline constexpr const char* kPath = "PATH";

/// A bound as a person writes it: 0.5, 1, 1e-06 (not 0.500000).
inline std::string plainNumber(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}

/// A whole number of type T in [lo, hi]: "must be an integer >= LO, got TEXT" when hi is the most T holds,
/// "must be an integer from LO to HI, got TEXT" otherwise or when the text is beyond what T holds.
template <class T>
CLI::Validator integerIn(T lo, T hi) {
  static_assert(std::is_integral_v<T>);
  const std::string range = "must be an integer from " + std::to_string(lo) + " to " + std::to_string(hi);
  const std::string rule = hi == std::numeric_limits<T>::max() ? "must be an integer >= " + std::to_string(lo) : range;
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        T value{};
        const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
        if (ec == std::errc::result_out_of_range) return range + ", got " + text;
        if (ec != std::errc() || end != text.data() + text.size()) return rule + ", got " + text;
        if (value < lo || value > hi) return rule + ", got " + text;
        return {};
      },
      rule.substr(std::string("must be an ").size()));
}

template <class T>
CLI::Validator integerAtLeast(T lo) {
  return integerIn<T>(lo, std::numeric_limits<T>::max());
}

/// The most worker threads (or tasks at a time) a command takes (docs/robustness.md, "Limits and non-regular
/// files"): far above the cores of any machine occsweep runs on, and a bound on what threads cost (a million cost
/// 550 MB before any work; 2^30 crashed the thread pool).
inline constexpr int kMaxThreads = 1024;

/// --threads (0: all cores) and run-local's --threads (at least 1): a whole number from `lo` to kMaxThreads.
inline CLI::Validator threadCount(int lo = 0) { return integerIn<int>(lo, kMaxThreads); }

/// A finite number in [lo, hi] (closed), or above lo (open) when `lo_open`; hi may be infinity.
inline CLI::Validator numberRule(double lo, double hi, bool lo_open) {
  std::string rule = "must be a number ";
  if (std::isinf(hi)) rule += (lo_open ? "> " : ">= ") + plainNumber(lo);
  else rule += (lo_open ? "in (" : "in [") + plainNumber(lo) + ", " + plainNumber(hi) + "]";
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        char* end = nullptr;
        const double v = text.empty() ? NAN : std::strtod(text.c_str(), &end);
        const bool parsed = !text.empty() && end == text.c_str() + text.size() && std::isfinite(v);
        if (!parsed || v < lo || (lo_open && v == lo) || v > hi) return rule + ", got " + text;
        return {};
      },
      rule.substr(std::string("must be a ").size()));
}

inline CLI::Validator numberIn(double lo, double hi) { return numberRule(lo, hi, false); }
inline CLI::Validator numberAbove(double lo) { return numberRule(lo, std::numeric_limits<double>::infinity(), true); }
inline CLI::Validator numberAtLeast(double lo) {
  return numberRule(lo, std::numeric_limits<double>::infinity(), false);
}
/// A probability: [0, 1].
inline CLI::Validator probability() { return numberIn(0.0, 1.0); }

/// The leaf of a voxel filter or of the truth's voxels, metres: a micrometre at least. Finer, float32 coordinates a
/// few metres from the origin lie farther apart than a leaf (nothing would be filtered), and a voxel's index, a
/// coordinate over the leaf, soon passes the 62 bits it is kept in (core/voxel_filter.hpp): 1e-300 failed on the
/// first point.
inline CLI::Validator voxelLeaf() { return numberAtLeast(1e-6); }

/// A name that tables and terminals show (a data set's, `import --name`): UTF-8 without control characters, since a
/// line break or an escape sequence in it would forge or erase lines wherever it is printed; the same rule as a
/// grid's name (path_component.hpp).
inline CLI::Validator printableName() {
  return CLI::Validator(
      [](std::string& text) {
        return hasControlCharacters(text) ? "must be UTF-8 text without control characters (line breaks, tabs, escape "
                                            "sequences), got '" + escapedControlCharacters(text) + "'"
                                          : std::string();
      },
      "");
}

}  // namespace occsweep::cli
