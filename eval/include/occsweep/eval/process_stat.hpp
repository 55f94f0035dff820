// What Linux says of a process by its PID (/proc/PID/stat and status): whether it runs, since when, and its peak
// memory. One reader for leftover temporaries (a temporary's process gone?) and run-local (a task still running? how
// much memory did it take?).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace occsweep {

struct ProcessStat {
  char state = 0;          ///< field 3: R, S, D, Z (a zombie: exited, not yet reaped), ...
  std::string start_time;  ///< field 22: clock ticks after boot; a PID reused later has another
};

/// /proc/PID/stat's state and start time; nothing when no such process is visible here.
[[nodiscard]] std::optional<ProcessStat> processStat(long pid);

/// A process's peak resident memory since its exec (/proc/PID/status VmHWM), in bytes; 0 when it cannot be read (no
/// such process, or a zombie). Not getrusage's ru_maxrss, which for a forked child starts at its parent's peak.
[[nodiscard]] std::uint64_t peakResidentBytes(long pid);

}  // namespace occsweep
