// Progress of long work on stderr (docs/cli.md, "Progress"): on a terminal a bar redrawn in place, with the rate
// and the time left; otherwise (a log, CI) a whole line every few seconds with the same numbers, and a last line.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>

namespace occsweep {

/// What a progress report says after `seconds` with `done` of `total` items: counts, percent, rate and time left
/// (the rate so far carried over what is left; no rate or time left before the first item).
/// e.g. "sweep knn-opt on ds: 1200/4050 maps (29.6 %), 85.1 maps/s, 34 s left, 14 s so far".
[[nodiscard]] std::string progressLine(const std::string& label, const std::string& unit, std::uint64_t done,
                                       std::uint64_t total, double seconds);
/// A duration for a person: "14 s", "3 min 05 s", "2 h 07 min".
[[nodiscard]] std::string durationText(double seconds);

class Progress {
 public:
  /// `unit`: what is counted, plural ("maps", "fits", "builds").
  Progress(std::string label, std::uint64_t total, bool quiet = false, std::string unit = "items");
  ~Progress();
  /// Thread-safe: n more items done.
  void advance(std::uint64_t n = 1);

  /// How often a log (stderr not a terminal) gets a line.
  static constexpr std::chrono::seconds kLogInterval{5};

 private:
  void print(bool final);
  std::string label_, unit_;
  std::uint64_t total_;
  std::atomic<std::uint64_t> done_{0};
  bool quiet_, tty_;
  std::mutex mutex_;
  std::chrono::steady_clock::time_point start_, last_;
};

/// Names a phase of long work before it starts ("reading data set ...", "recording ..."), on its own line on
/// stderr unless quiet: no phase is silent.
void announcePhase(const std::string& what, bool quiet);

}  // namespace occsweep
