// Bounded access to untrusted bytes and text for the import readers: every read is checked against
// what is left, every failure is a DataError naming the file and the byte offset or line.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "data_error.hpp"

namespace occsweep {

/// Largest input file the readers accept (a depth frame is ~1 MB, a big PLY a few hundred MB).
inline constexpr std::uint64_t kMaxImportFileBytes = std::uint64_t(4) << 30;

/// Every reader of an input file calls this first: DataError naming the file and what it is when it
/// is not a regular file (missing, a folder, a FIFO, which would make a reader wait forever, a socket, a device,
/// a symlink loop or a dangling link), so that no reader hangs or reports "file is missing" for a folder.
void requireRegularFile(const std::filesystem::path& file);

/// The whole file; DataError when requireRegularFile refuses it, it is unreadable, or larger than `max_bytes`.
[[nodiscard]] std::string readFileBytes(const std::filesystem::path& file,
                                        std::uint64_t max_bytes = kMaxImportFileBytes);

/// The first line of `file` (without its line break), read from a regular file only (a link is followed: callers
/// that must refuse one check it) and at most `max_bytes` of it: nothing when the file is not a regular file, cannot
/// be read, or has no line break within `max_bytes` (a marker
/// line occsweep writes is short; a file of gigabytes without a line break is never read whole).
[[nodiscard]] std::optional<std::string> readFirstLine(const std::filesystem::path& file, std::size_t max_bytes);

/// The whole file parsed as JSON: readJsonBytes' refusals, then a DataError "FILE: not valid JSON: ..." when it is
/// not (a syntax error, a truncated file, a number like 1e999 that no double holds), or gives a key twice in one
/// object. One home for every JSON input: manifests, results, plans.
[[nodiscard]] nlohmann::json readJsonFile(const std::filesystem::path& file);
/// The bytes of a JSON input (readJsonFile, a grid): readFileBytes' refusals, and a LimitError naming the file and
/// --max-json-bytes for one past limits().json_bytes, before a byte is read.
[[nodiscard]] std::string readJsonBytes(const std::filesystem::path& file);

/// How much of a file jsonFormatField reads: every JSON output of occsweep has its "format" within its first
/// kilobytes (the keys before it, in name order, are short: "complete", "dataset", "files", ...).
inline constexpr std::size_t kJsonFormatPrefixBytes = std::size_t(1) << 20;
/// The top-level "format" string of a regular file that begins as a JSON object, read from its first
/// kJsonFormatPrefixBytes alone (an output of gigabytes is never read whole to learn whose it is): nothing when it
/// is not a regular file, cannot be read, or has no such field there.
[[nodiscard]] std::optional<std::string> jsonFormatField(const std::filesystem::path& file);
/// `text` (the bytes of `file`) parsed as JSON, with readJsonFile's error.
[[nodiscard]] nlohmann::json parseJsonText(std::string_view text, const std::filesystem::path& file);
/// parseJsonText, and a key given twice in one object is refused (DataError naming the file and the key's path):
/// JSON parsers keep only the last, so a hand-written file (a grid) would silently lose the first.
[[nodiscard]] nlohmann::json parseJsonTextUniqueKeys(std::string_view text, const std::filesystem::path& file);

/// Sequential binary reader over a byte buffer; never reads past the end.
class ByteReader {
 public:
  ByteReader(std::string_view bytes, std::filesystem::path file) : bytes_(bytes), file_(std::move(file)) {}

  [[nodiscard]] std::size_t offset() const { return pos_; }
  [[nodiscard]] std::size_t remaining() const { return bytes_.size() - pos_; }
  [[nodiscard]] const std::filesystem::path& file() const { return file_; }
  /// Throws unless `n` more bytes are there; `what` says what was being read.
  void need(std::uint64_t n, const std::string& what) const;
  [[nodiscard]] std::string_view take(std::size_t n, const std::string& what);
  [[nodiscard]] std::uint32_t u32le(const std::string& what);
  [[nodiscard]] std::int32_t i32le(const std::string& what);
  [[nodiscard]] double f64le(const std::string& what);
  /// Throws a DataError at the current offset.
  [[noreturn]] void fail(const std::string& what, const std::string& rule) const;

 private:
  std::string_view bytes_;
  std::filesystem::path file_;
  std::size_t pos_ = 0;
};

/// Line-by-line text with whitespace-separated tokens; line numbers start at 1.
class TextLines {
 public:
  TextLines(std::string_view text, std::filesystem::path file, std::size_t first_line = 1)
      : text_(text), file_(std::move(file)), line_(first_line - 1) {}

  /// Next line's tokens (skips nothing); false at the end.
  bool next(std::vector<std::string_view>& tokens);
  /// Next line that is neither blank nor a `#` comment.
  bool nextData(std::vector<std::string_view>& tokens);
  [[nodiscard]] std::size_t line() const { return line_; }
  /// Byte offset of the next line (the text's size after the last line, even one without a newline).
  [[nodiscard]] std::size_t offset() const { return pos_ < text_.size() ? pos_ : text_.size(); }
  [[nodiscard]] const std::filesystem::path& file() const { return file_; }
  [[noreturn]] void fail(const std::string& rule) const;
  /// A finite number, or a DataError naming the line and the column.
  [[nodiscard]] double number(std::string_view token, std::size_t column, const std::string& what) const;

 private:
  std::string_view text_;
  std::filesystem::path file_;
  std::size_t pos_ = 0, line_ = 0;
};

/// One binary number of `size` bytes (1, 2, 4 or 8) and `kind` 'i' (signed), 'u' (unsigned) or 'f' (IEEE float,
/// size 4 or 8) at `p`, as a double; the caller has checked that the bytes are there.
[[nodiscard]] double decodeScalar(const char* p, int size, char kind, bool big_endian);

/// Parses a whole token as a double (no NaN, no infinity); false when it is not one.
[[nodiscard]] bool parseFiniteDouble(std::string_view token, double& out);
/// Parses a whole token as an unsigned integer; false when it is not one or overflows.
[[nodiscard]] bool parseUnsigned(std::string_view token, std::uint64_t& out);

}  // namespace occsweep
