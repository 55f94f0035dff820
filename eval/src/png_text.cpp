#include "occsweep/eval/png_text.hpp"

#include <cstdint>
#include <fstream>

namespace occsweep {

std::string pngText(const std::filesystem::path& file, const std::string& keyword) {
  std::ifstream in(file, std::ios::binary);
  char signature[8];
  if (!in.read(signature, 8) || std::string(signature, 8) != "\x89PNG\r\n\x1a\n") return "";
  for (int chunks = 0; chunks < 64; ++chunks) {  // matplotlib writes its text chunks right after IHDR
    unsigned char head[8];
    if (!in.read(reinterpret_cast<char*>(head), 8)) return "";
    const std::uint32_t length = std::uint32_t(head[0]) << 24 | std::uint32_t(head[1]) << 16 |
                                 std::uint32_t(head[2]) << 8 | head[3];
    const std::string type(reinterpret_cast<char*>(head) + 4, 4);
    if (type == "IDAT" || type == "IEND" || length > (1u << 20)) return "";
    std::string data(length, '\0');
    if (!in.read(data.data(), length) || !in.ignore(4)) return "";  // the data, then its CRC
    if (type == "tEXt" && data.starts_with(keyword + '\0')) return data.substr(keyword.size() + 1);
  }
  return "";
}

}  // namespace occsweep
