#include "occsweep/sweeps/progress.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <sys/ioctl.h>
#include <unistd.h>

#include "occsweep/io/control_characters.hpp"

namespace occsweep {

std::string durationText(double seconds) {
  const long s = std::lround(std::max(0.0, seconds));
  char text[48];
  if (s < 60) std::snprintf(text, sizeof text, "%ld s", s);
  else if (s < 3600) std::snprintf(text, sizeof text, "%ld min %02ld s", s / 60, s % 60);
  else std::snprintf(text, sizeof text, "%ld h %02ld min", s / 3600, (s % 3600) / 60);
  return text;
}

namespace {

std::string rateText(double per_second, const std::string& unit) {
  char text[64];
  std::snprintf(text, sizeof text, per_second >= 100 ? "%.0f %s/s" : "%.3g %s/s", per_second, unit.c_str());
  return text;
}

}  // namespace

std::string progressLine(const std::string& label, const std::string& unit, std::uint64_t done, std::uint64_t total,
                         double seconds) {
  char counts[96];
  std::snprintf(counts, sizeof counts, "%llu/%llu %s (%.1f %%)", (unsigned long long)done, (unsigned long long)total,
                unit.c_str(), total ? 100.0 * double(done) / double(total) : 100.0);
  std::string line = label + ": " + counts;
  if (done > 0 && seconds > 0) {
    const double rate = double(done) / seconds;
    line += ", " + rateText(rate, unit);
    if (done < total) line += ", " + durationText(double(total - done) / rate) + " left";
  }
  return line + ", " + durationText(seconds) + (done >= total ? " in all" : " so far");
}

Progress::Progress(std::string label, std::uint64_t total, bool quiet, std::string unit)
    : label_(escapedControlCharacters(label)),  // a data set's name in it shows its control characters escaped
      unit_(std::move(unit)), total_(total), quiet_(quiet), tty_(::isatty(2) != 0),
      start_(std::chrono::steady_clock::now()), last_(start_) {}

Progress::~Progress() {
  if (!quiet_) print(true);
}

void Progress::advance(std::uint64_t n) {
  done_ += n;
  if (quiet_) return;
  const auto now = std::chrono::steady_clock::now();
  const std::chrono::steady_clock::duration every =
      tty_ ? std::chrono::steady_clock::duration(std::chrono::milliseconds(200)) : kLogInterval;
  std::unique_lock lock(mutex_, std::try_to_lock);
  if (!lock.owns_lock() || now - last_ < every) return;
  last_ = now;
  print(false);
}

void Progress::print(bool final) {
  const std::uint64_t done = done_.load();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const std::string line = progressLine(label_, unit_, done, total_, seconds);
  if (tty_) {
    const double fraction = total_ ? double(done) / double(total_) : 1.0;
    const int width = 20, filled = int(fraction * width);
    // A line that redraws itself with \r must not wrap: on a narrower terminal every redraw would leave a line
    // behind. Cut to the terminal's width but its last column (where some terminals wrap); the final line whole.
    std::string shown = line;
    winsize terminal{};
    if (!final && ::ioctl(STDERR_FILENO, TIOCGWINSZ, &terminal) == 0 && terminal.ws_col > 0) {
      const std::size_t room = std::size_t(std::max(0, int(terminal.ws_col) - (width + 3) - 1));
      if (shown.size() > room) shown.resize(room);
    }
    // \033[K clears what a longer earlier line left on the right
    std::fprintf(stderr, "\r[%.*s%*s] %s\033[K%s", filled, "####################", width - filled, "", shown.c_str(),
                 final ? "\n" : "");
  } else {
    std::fprintf(stderr, "%s\n", line.c_str());
  }
  std::fflush(stderr);
}

void announcePhase(const std::string& what, bool quiet) {
  if (quiet) return;
  std::cerr << escapedControlCharacters(what) << '\n';  // a data set's name or path, a grid's name
}

}  // namespace occsweep
