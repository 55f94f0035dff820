// Bounded access to untrusted bytes and text for the import readers: every read is checked against what is left,
// every failure a DataError naming the file and the byte offset or line.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "occsweep/io/data_error.hpp"

namespace occsweep {

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
  /// A finite number, or a DataError naming the line, the column and why: a `#` comment after numbers (a comment
  /// takes a whole line), NaN or infinity, out of a double's range (1e400), or not a number.
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
