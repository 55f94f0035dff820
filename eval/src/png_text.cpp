#include "occsweep/eval/png_text.hpp"

#include <cstdint>
#include <fstream>
#include <stdexcept>

namespace occsweep {
namespace {

constexpr std::string_view kSignature = "\x89PNG\r\n\x1a\n";

// The CRC-32 every PNG chunk ends with (ISO 3309, the PNG specification's section 5.5), over type and data.
std::uint32_t chunkCrc(std::string_view bytes) {
  std::uint32_t c = 0xFFFFFFFFu;
  for (unsigned char b : bytes) {
    c ^= b;
    for (int k = 0; k < 8; ++k) c = (c & 1u) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
  }
  return c ^ 0xFFFFFFFFu;
}

void appendBigEndian(std::string& out, std::uint32_t v) {
  for (int shift = 24; shift >= 0; shift -= 8) out += char((v >> shift) & 0xFFu);
}

}  // namespace

std::string pngWithText(std::string_view png, const std::string& keyword, const std::string& text) {
  constexpr std::size_t kIhdrEnd = 8 + 8 + 13 + 4;  // signature, then IHDR: length and type, 13 bytes, CRC
  if (png.size() < kIhdrEnd || png.substr(0, 8) != kSignature || png.substr(12, 4) != "IHDR")
    throw std::invalid_argument("pngWithText: not a PNG that starts with its IHDR chunk");
  const std::string body = "tEXt" + keyword + '\0' + text;
  std::string out(png.substr(0, kIhdrEnd));
  appendBigEndian(out, std::uint32_t(body.size() - 4));
  out += body;
  appendBigEndian(out, chunkCrc(body));
  out += png.substr(kIhdrEnd);
  return out;
}

std::string pngText(const std::filesystem::path& file, const std::string& keyword) {
  // The whole file walked as the format defines it: IHDR first, every chunk's CRC right, IEND last and nothing after
  // it. A file that is not a well-formed PNG proves nothing, whatever text it carries (docs/robustness.md).
  constexpr std::uint32_t kMaxChunk = 64u << 20;
  std::ifstream in(file, std::ios::binary);
  char signature[8];
  if (!in.read(signature, 8) || std::string_view(signature, 8) != kSignature) return "";
  std::string found;
  for (bool first = true;; first = false) {
    unsigned char head[8];
    if (!in.read(reinterpret_cast<char*>(head), 8)) return "";
    const std::uint32_t length = std::uint32_t(head[0]) << 24 | std::uint32_t(head[1]) << 16 |
                                 std::uint32_t(head[2]) << 8 | head[3];
    if (length > kMaxChunk) return "";
    std::string chunk(reinterpret_cast<char*>(head) + 4, 4);  // type, then data: what the CRC covers
    const std::string type = chunk;
    if (first != (type == "IHDR")) return "";
    chunk.resize(4 + std::size_t(length));
    unsigned char crc[4];
    if (!in.read(chunk.data() + 4, length) || !in.read(reinterpret_cast<char*>(crc), 4)) return "";
    const std::uint32_t stored = std::uint32_t(crc[0]) << 24 | std::uint32_t(crc[1]) << 16 |
                                 std::uint32_t(crc[2]) << 8 | crc[3];
    if (stored != chunkCrc(chunk)) return "";
    const std::string_view data = std::string_view(chunk).substr(4);
    if (type == "tEXt" && found.empty() && data.starts_with(keyword + '\0')) found = data.substr(keyword.size() + 1);
    if (type == "IEND") return in.peek() == std::char_traits<char>::eof() ? found : "";
  }
}

ReplaceableOutput markedPngOutput(const std::string& name, const std::string& software) {
  return {name, [software](const std::filesystem::path& file) { return pngText(file, "Software") == software; }};
}

}  // namespace occsweep
