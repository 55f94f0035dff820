// Parsing "I/N" options (--shard, --group) for the commands that take them.
#pragma once

#include <stdexcept>
#include <string>
#include <utility>

namespace occsweep::cli {

/// "I/N" with 0 <= I < N; std::invalid_argument naming the option otherwise.
inline std::pair<std::uint64_t, std::uint64_t> parseFraction(const std::string& text, const std::string& option) {
  const auto slash = text.find('/');
  try {
    if (slash == std::string::npos) throw std::invalid_argument("");
    std::size_t used_a = 0, used_b = 0;
    const std::string a = text.substr(0, slash), b = text.substr(slash + 1);
    if (a.empty() || b.empty() || a[0] == '-' || b[0] == '-') throw std::invalid_argument("");
    const auto i = std::stoull(a, &used_a), n = std::stoull(b, &used_b);
    if (used_a != a.size() || used_b != b.size() || n == 0 || i >= n) throw std::invalid_argument("");
    return {i, n};
  } catch (const std::exception&) {
    throw std::invalid_argument(option + " '" + text + "': expected I/N with 0 <= I < N");
  }
}

}  // namespace occsweep::cli
