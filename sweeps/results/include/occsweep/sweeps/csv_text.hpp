// The fields of every CSV occsweep writes (`compare --csv`, `results export`; docs/results-format.md, "CSV"): one
// number format and one quoting rule, so that files of several commands read into one frame.
#pragma once

#include <charconv>
#include <cmath>
#include <string>

namespace occsweep {

/// The shortest text that reads back to the same double (std::to_chars: 0.98 is "0.98", never
/// "0.97999999999999998"); empty, CSV's missing value, for NaN and the infinities.
[[nodiscard]] inline std::string csvNumber(double v) {
  if (!std::isfinite(v)) return "";
  char buf[32];
  const auto end = std::to_chars(buf, buf + sizeof buf, v).ptr;
  return std::string(buf, end);
}

/// `s` as one CSV field (RFC 4180): quoted, with its quotes doubled, when it holds a comma, quote or line break.
[[nodiscard]] inline std::string csvField(const std::string& s) {
  if (s.find_first_of(",\"\r\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char ch : s) out += ch == '"' ? std::string("\"\"") : std::string(1, ch);
  return out + "\"";
}

}  // namespace occsweep
