// An enum's names as they stand in results files, settings and on the command line: one table per enum, from
// which both directions (and the list CLI11's IsMember checks against) are read, so they cannot drift apart.
#pragma once

#include <array>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace occsweep {

/// The names of the N values of `Enum`, in the enum's order; `what` names the setting in refusals ("variant").
template <class Enum, std::size_t N>
struct EnumNames {
  std::string_view what;
  std::array<std::pair<Enum, const char*>, N> names;

  /// The name of `value`.
  [[nodiscard]] constexpr const char* text(Enum value) const;
  /// The value of `name`; throws std::invalid_argument naming `name` and the accepted names:
  /// "variant 'x': must be default or literal".
  [[nodiscard]] Enum parse(std::string_view name) const;
  [[nodiscard]] constexpr bool accepts(std::string_view name) const;
  /// The names in order, for CLI11's IsMember (whose help lists them in this order).
  [[nodiscard]] std::vector<std::string> list() const;
  /// "a or b" (or "a, b or c"), each name between `quote`s.
  [[nodiscard]] std::string alternatives(std::string_view quote = "") const;
};

// ---------------------------------------------------------------------------------------------------------

template <class Enum, std::size_t N>
constexpr const char* EnumNames<Enum, N>::text(Enum value) const {
  for (const auto& [v, name] : names)
    if (v == value) return name;
  throw std::invalid_argument(std::string(what) + ": a value without a name");
}

template <class Enum, std::size_t N>
Enum EnumNames<Enum, N>::parse(std::string_view name) const {
  for (const auto& [v, n] : names)
    if (std::string_view(n) == name) return v;
  throw std::invalid_argument(std::string(what) + " '" + std::string(name) + "': must be " + alternatives());
}

template <class Enum, std::size_t N>
constexpr bool EnumNames<Enum, N>::accepts(std::string_view name) const {
  for (const auto& entry : names)
    if (std::string_view(entry.second) == name) return true;
  return false;
}

template <class Enum, std::size_t N>
std::vector<std::string> EnumNames<Enum, N>::list() const {
  std::vector<std::string> out;
  for (const auto& entry : names) out.emplace_back(entry.second);
  return out;
}

template <class Enum, std::size_t N>
std::string EnumNames<Enum, N>::alternatives(std::string_view quote) const {
  std::string out;
  for (std::size_t i = 0; i < N; ++i) {
    if (i > 0) out += i + 1 == N ? " or " : ", ";
    out.append(quote).append(names[i].second).append(quote);
  }
  return out;
}

}  // namespace occsweep
