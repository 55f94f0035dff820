#include "occsweep/io/control_characters.hpp"
#include "occsweep/io/child_process.hpp"

#include <cstdio>

namespace occsweep {
namespace {

// The length of the well-formed UTF-8 sequence at the start of `text` (RFC 3629: no overlong form, no surrogate,
// nothing above U+10FFFF), and its code point; length 0 when there is none.
std::size_t sequenceAt(std::string_view text, char32_t& code_point) {
  const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(text[i]); };
  const unsigned char lead = byte(0);
  const std::size_t n = lead < 0x80 ? 1 : lead >= 0xC2 && lead <= 0xDF ? 2 : lead >= 0xE0 && lead <= 0xEF ? 3
                                                                        : lead >= 0xF0 && lead <= 0xF4 ? 4 : 0;
  if (n == 0 || text.size() < n) return 0;
  code_point = n == 1 ? lead : lead & (0x7F >> n);
  for (std::size_t k = 1; k < n; ++k) {
    if ((byte(k) & 0xC0) != 0x80) return 0;
    code_point = (code_point << 6) | (byte(k) & 0x3F);
  }
  const bool overlong = (n == 3 && code_point < 0x800) || (n == 4 && code_point < 0x10000);
  const bool surrogate = code_point >= 0xD800 && code_point <= 0xDFFF;
  return overlong || surrogate || code_point > 0x10FFFF ? 0 : n;
}

std::string escape(const char* format, unsigned value) {
  char text[12];
  std::snprintf(text, sizeof text, format, value);
  return text;
}

bool isControlCharacter(char32_t c) {
  return c < 0x20 || (c >= 0x7F && c <= 0x9F) || (c >= 0x202A && c <= 0x202E) || (c >= 0x2066 && c <= 0x2069);
}

}  // namespace

std::vector<Utf8Character> utf8Characters(std::string_view text) {
  std::vector<Utf8Character> out;
  while (!text.empty()) {
    char32_t code_point = kNotUtf8;
    const std::size_t n = sequenceAt(text, code_point);
    out.push_back({n ? code_point : kNotUtf8, text.substr(0, n ? n : 1)});
    text.remove_prefix(n ? n : 1);
  }
  return out;
}

std::string escapedControlCharacters(std::string_view text) {
  std::string out;
  for (const Utf8Character& c : utf8Characters(text)) {
    if (c.code_point == '\n' || c.code_point == '\r' || c.code_point == '\t')
      out += c.code_point == '\n' ? "\\n" : c.code_point == '\r' ? "\\r" : "\\t";
    else if (c.code_point == kNotUtf8 || (isControlCharacter(c.code_point) && c.code_point <= 0x7F))
      out += escape("\\x%02x", static_cast<unsigned char>(c.bytes[0]));
    else if (isControlCharacter(c.code_point))
      out += escape("\\u%04x", c.code_point);
    else
      out += c.bytes;
  }
  return out;
}

std::string shownShellWord(const std::string& arg) {
  if (!hasControlCharacters(arg)) return shellWord(arg);
  std::string quoted;  // \ and ' first: the escapes added next are bash's own
  for (const char c : arg) quoted += c == '\\' ? std::string("\\\\") : c == '\'' ? std::string("\\'") : std::string(1, c);
  return "$'" + escapedControlCharacters(quoted) + "'";
}

}  // namespace occsweep
