#include "occsweep/sweeps/progress.hpp"

#include <cstdio>
#include <unistd.h>

namespace occsweep {

Progress::Progress(std::string label, std::uint64_t total, bool quiet)
    : label_(std::move(label)), total_(total), quiet_(quiet), tty_(::isatty(2) != 0),
      start_(std::chrono::steady_clock::now()), last_(start_) {}

Progress::~Progress() {
  if (!quiet_) print(true);
}

void Progress::advance(std::uint64_t n) {
  done_ += n;
  if (quiet_) return;
  const auto now = std::chrono::steady_clock::now();
  const auto every = tty_ ? std::chrono::milliseconds(200) : std::chrono::milliseconds(10000);
  std::unique_lock lock(mutex_, std::try_to_lock);
  if (!lock.owns_lock() || now - last_ < every) return;
  last_ = now;
  print(false);
}

void Progress::print(bool final) {
  const std::uint64_t done = done_.load();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double fraction = total_ ? double(done) / double(total_) : 1.0;
  if (tty_) {
    const int width = 30, filled = int(fraction * width);
    std::fprintf(stderr, "\r%s [%.*s%*s] %llu/%llu %.0f s%s", label_.c_str(), filled,
                 "##############################", width - filled, "", (unsigned long long)done,
                 (unsigned long long)total_, seconds, final ? "\n" : "");
  } else {
    std::fprintf(stderr, "%s: %llu/%llu (%.0f%%) after %.0f s\n", label_.c_str(), (unsigned long long)done,
                 (unsigned long long)total_, fraction * 100.0, seconds);
  }
  std::fflush(stderr);
}

}  // namespace occsweep
