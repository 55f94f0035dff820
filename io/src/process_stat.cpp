#include "occsweep/io/process_stat.hpp"

#include <fstream>
#include <iterator>
#include <sstream>

namespace occsweep {

std::optional<ProcessStat> processStat(long pid) {
  if (pid <= 0) return std::nullopt;
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  const std::string stat((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  // The command name (field 2) is in parentheses and may hold spaces and ')': the fields start after the last ')'.
  const std::size_t comm_end = stat.rfind(')');
  if (comm_end == std::string::npos || comm_end + 2 >= stat.size()) return std::nullopt;
  std::istringstream fields(stat.substr(comm_end + 2));
  ProcessStat out;
  std::string field;
  for (int i = 3; i <= 22 && fields >> field; ++i) {
    if (i == 3) out.state = field.empty() ? char(0) : field[0];
    if (i == 22) out.start_time = field;
  }
  if (out.start_time.empty()) return std::nullopt;
  return out;
}

}  // namespace occsweep
