// Numbers in messages and tables as a person writes them: "0.97", "3", not "0.970000".
#pragma once

#include <string>

namespace occsweep::detail {

/// `v` as std::to_string gives it (six decimals), trailing zeros and a trailing point dropped.
[[nodiscard]] inline std::string fmt(double v) {
  std::string s = std::to_string(v);
  while (s.size() > 1 && s.back() == '0') s.pop_back();
  if (!s.empty() && s.back() == '.') s.pop_back();
  return s;
}

}  // namespace occsweep::detail
