// A PNG's text chunks: the mark occsweep's figures carry (matplotlib's `metadata={"Software": ...}`), by which a
// figure at an output's name is proven occsweep's own (docs/robustness.md, "Ownership").
#pragma once

#include <filesystem>
#include <string>

namespace occsweep {

/// The value of `file`'s tEXt chunk of `keyword`, read chunk by chunk as the PNG format defines it (up to the
/// first image data); "" when the file is not a PNG or has no such chunk.
[[nodiscard]] std::string pngText(const std::filesystem::path& file, const std::string& keyword);

}  // namespace occsweep
