// Progress of long work on stderr: a bar on a terminal, a line every few seconds otherwise.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>

namespace occsweep {

class Progress {
 public:
  Progress(std::string label, std::uint64_t total, bool quiet = false);
  ~Progress();
  /// Thread-safe: n more items done.
  void advance(std::uint64_t n = 1);

 private:
  void print(bool final);
  std::string label_;
  std::uint64_t total_;
  std::atomic<std::uint64_t> done_{0};
  bool quiet_, tty_;
  std::mutex mutex_;
  std::chrono::steady_clock::time_point start_, last_;
};

}  // namespace occsweep
