// Control characters in names and paths that come from users' files and arguments: found, to refuse them where a
// name is made (grid names, `import --name`), and escaped wherever such a text is printed to a terminal, where a
// line break or an escape sequence would forge or erase lines (docs/robustness.md, "Messages, formats and the
// cluster").
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace occsweep {

/// One character of UTF-8 text: its code point and its bytes. A byte that does not start a well-formed sequence is
/// a character of its own, with code point kNotUtf8.
struct Utf8Character {
  char32_t code_point;
  std::string_view bytes;
};
inline constexpr char32_t kNotUtf8 = 0xFFFFFFFF;

/// The characters of `text`, in order.
[[nodiscard]] std::vector<Utf8Character> utf8Characters(std::string_view text);

/// `text` with every control character and every byte that is not UTF-8 written as an escape a reader can see:
/// `\n`, `\r`, `\t`, `\x1b` (the other C0 controls and DEL), `\u0085` (C1 controls, U+0080-U+009F, and the
/// bidirectional controls U+202A-U+202E and U+2066-U+2069, which reorder the text shown around them), `\xff` (a byte
/// that is not UTF-8). Text without any comes back unchanged.
[[nodiscard]] std::string escapedControlCharacters(std::string_view text);

/// Whether `text` holds a control character or a byte that is not UTF-8.
[[nodiscard]] inline bool hasControlCharacters(std::string_view text) { return escapedControlCharacters(text) != text; }

/// `arg` as one shell word a terminal shows as it is and bash reads back as `arg`: shellWord (child_process.hpp)
/// where it holds no control character, else bash's $'...' quoting with escapedControlCharacters' escapes.
[[nodiscard]] std::string shownShellWord(const std::string& arg);

}  // namespace occsweep
