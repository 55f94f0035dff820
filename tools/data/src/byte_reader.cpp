// The import readers' bounded access to bytes and text (byte_reader.hpp).
#include "occsweep/data/byte_reader.hpp"

#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>

namespace occsweep {

void ByteReader::need(std::uint64_t n, const std::string& what) const {
  if (n > remaining())
    fail(what, "needs " + std::to_string(n) + " bytes, only " + std::to_string(remaining()) +
                   " left: truncated file or wrong count");
}

std::string_view ByteReader::take(std::size_t n, const std::string& what) {
  need(n, what);
  const auto out = bytes_.substr(pos_, n);
  pos_ += n;
  return out;
}

std::uint32_t ByteReader::u32le(const std::string& what) {
  const auto b = take(4, what);
  std::uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(b[std::size_t(i)]);
  return v;
}

std::int32_t ByteReader::i32le(const std::string& what) { return static_cast<std::int32_t>(u32le(what)); }

double ByteReader::f64le(const std::string& what) {
  const auto b = take(8, what);
  std::uint64_t v = 0;
  for (int i = 7; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(b[std::size_t(i)]);
  return std::bit_cast<double>(v);
}

void ByteReader::fail(const std::string& what, const std::string& rule) const {
  throw DataError(file_, "byte " + std::to_string(pos_) + (what.empty() ? "" : " (" + what + ")"), rule);
}

bool TextLines::next(std::vector<std::string_view>& tokens) {
  tokens.clear();
  if (pos_ >= text_.size()) return false;
  std::size_t end = text_.find('\n', pos_);
  if (end == std::string_view::npos) end = text_.size();
  std::string_view line = text_.substr(pos_, end - pos_);
  pos_ = end + 1;
  ++line_;
  std::size_t i = 0;
  auto space = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; };
  while (i < line.size()) {
    while (i < line.size() && space(line[i])) ++i;
    std::size_t j = i;
    while (j < line.size() && !space(line[j])) ++j;
    if (j > i) tokens.push_back(line.substr(i, j - i));
    i = j;
  }
  return true;
}

bool TextLines::nextData(std::vector<std::string_view>& tokens) {
  while (next(tokens))
    if (!tokens.empty() && tokens[0][0] != '#') return true;
  return false;
}

void TextLines::fail(const std::string& rule) const {
  throw DataError(file_, "line " + std::to_string(line_), rule);
}

namespace {

/// Why `token`, which parseFiniteDouble refused, is no finite number.
std::string notFiniteWhy(std::string_view token) {
  if (token.find_first_of("nNiI") != std::string_view::npos) return "NaN and infinite values are not allowed";
  if (!token.empty() && token[0] == '+') token.remove_prefix(1);
  double v = 0;
  const auto r = std::from_chars(token.data(), token.data() + token.size(), v);
  if (r.ec == std::errc::result_out_of_range && r.ptr == token.data() + token.size())
    return "out of a double's range";
  return "not a number";
}

}  // namespace

double TextLines::number(std::string_view token, std::size_t column, const std::string& what) const {
  double v = 0;
  if (parseFiniteDouble(token, v)) return v;
  const std::string column_is = "column " + std::to_string(column + 1), shown(token.substr(0, 32));
  if (!token.empty() && token[0] == '#')  // a whole-line comment is skipped (nextData); one after numbers is not
    fail(column_is + " is \"" + shown + "\", a comment after the numbers: a # comment takes a whole line (as "
                     "numpy.savetxt writes one); move it to a line of its own");
  fail(column_is + " (" + what + ") is \"" + shown + "\": " + notFiniteWhy(token));
}

double decodeScalar(const char* p, int size, char kind, bool big_endian) {
  std::uint64_t v = 0;
  for (int i = 0; i < size; ++i) {
    const int at = big_endian ? i : size - 1 - i;
    v = (v << 8) | static_cast<unsigned char>(p[at]);
  }
  if (kind == 'f') return size == 4 ? double(std::bit_cast<float>(std::uint32_t(v))) : std::bit_cast<double>(v);
  if (kind == 'u') return double(v);
  const int shift = 64 - 8 * size;  // sign-extend
  return double(static_cast<std::int64_t>(v << shift) >> shift);
}

bool parseFiniteDouble(std::string_view token, double& out) {
  if (!token.empty() && token[0] == '+') token.remove_prefix(1);  // from_chars refuses a leading '+'
  const auto r = std::from_chars(token.data(), token.data() + token.size(), out);
  return r.ec == std::errc() && r.ptr == token.data() + token.size() && std::isfinite(out);
}

bool parseUnsigned(std::string_view token, std::uint64_t& out) {
  const auto r = std::from_chars(token.data(), token.data() + token.size(), out);
  return r.ec == std::errc() && r.ptr == token.data() + token.size() && !token.empty();
}

}  // namespace occsweep
