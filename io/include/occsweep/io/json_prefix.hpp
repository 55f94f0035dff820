// Whose a JSON output is, read from its first bytes alone: an output of gigabytes is never read whole, or parsed
// into a tree, to decide whether --force may replace it (docs/io.md, "Reading within a bound").
#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

namespace occsweep {

/// How much of a file jsonFormatField reads: every JSON output of occsweep has its "format" within its first
/// kilobytes (the keys before it, in name order, are short: "complete", "dataset", "files", ...).
inline constexpr std::size_t kJsonFormatPrefixBytes = std::size_t(1) << 20;
/// The top-level "format" string of a regular file that begins as a JSON object, read from its first
/// kJsonFormatPrefixBytes alone (an output of gigabytes is never read whole to learn whose it is): nothing when it
/// is not a regular file, cannot be read, or has no such field there.
[[nodiscard]] std::optional<std::string> jsonFormatField(const std::filesystem::path& file);

/// Every SAX event accepted, a syntax error ending the parse: a base for readers that look at a few events only.
struct JsonEvents : nlohmann::json::json_sax_t {
  using json = nlohmann::json;
  bool null() override { return true; }
  bool boolean(bool) override { return true; }
  bool number_integer(json::number_integer_t) override { return true; }
  bool number_unsigned(json::number_unsigned_t) override { return true; }
  bool number_float(json::number_float_t, const json::string_t&) override { return true; }
  bool string(json::string_t&) override { return true; }
  bool binary(json::binary_t&) override { return true; }
  bool start_object(std::size_t) override { return true; }
  bool key(json::string_t&) override { return true; }
  bool end_object() override { return true; }
  bool start_array(std::size_t) override { return true; }
  bool end_array() override { return true; }
  bool parse_error(std::size_t, const std::string&, const json::exception&) override { return false; }
};

}  // namespace occsweep
