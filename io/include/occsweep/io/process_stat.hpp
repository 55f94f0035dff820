// What Linux says of a process by its PID (/proc/PID/stat): whether it runs, and since when. One reader for
// leftover temporaries (a temporary's process gone?) and run-local (a task still running?).
#pragma once

#include <optional>
#include <string>

namespace occsweep {

struct ProcessStat {
  char state = 0;          ///< field 3: R, S, D, Z (a zombie: exited, not yet reaped), ...
  std::string start_time;  ///< field 22: clock ticks after boot; a PID reused later has another
};

/// /proc/PID/stat's state and start time; nothing when no such process is visible here.
[[nodiscard]] std::optional<ProcessStat> processStat(long pid);

}  // namespace occsweep
