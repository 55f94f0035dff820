// A PNG's text chunks: the mark occsweep's figures carry (matplotlib's `metadata={"Software": ...}`), by which a
// figure at an output's name is proven occsweep's own (docs/io.md, "Ownership").
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "occsweep/io/output_file.hpp"

namespace occsweep {

/// The value of `file`'s first tEXt chunk of `keyword`; "" when it has none, or is not a well-formed PNG (IHDR
/// first, every chunk's CRC right, IEND last with nothing after it, no chunk above 64 MB).
[[nodiscard]] std::string pngText(const std::filesystem::path& file, const std::string& keyword);

/// A figure of occsweep's, proven by a well-formed PNG whose Software text chunk is exactly `software` (what matplotlib
/// writes from `metadata={"Software": ...}`, or pngWithText): what --force, or a re-run, may replace.
[[nodiscard]] ReplaceableOutput markedPngOutput(const std::string& name, const std::string& software);

/// `png` (a whole PNG file's bytes) with a tEXt chunk `keyword`=`text` inserted right after its IHDR chunk, as
/// matplotlib places its own: for images written by an encoder that writes none (libpng's simplified API).
/// std::invalid_argument when `png` does not start with the signature and IHDR.
[[nodiscard]] std::string pngWithText(std::string_view png, const std::string& keyword, const std::string& text);

}  // namespace occsweep
