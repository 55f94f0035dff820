// FNV-1a 64: the content hash of data sets, grid files and results (not cryptographic, only for identity).
#pragma once

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include "data_error.hpp"
#include "bounded_read.hpp"

namespace occsweep {

class Fnv1a {
 public:
  void feed(std::string_view bytes) {
    for (unsigned char c : bytes) h_ = (h_ ^ c) * 0x100000001b3ull;
  }
  /// Feeds a whole file; DataError when it cannot be read.
  void feedFile(const std::filesystem::path& file) {
    requireRegularFile(file);
    std::ifstream in(file, std::ios::binary);
    if (!in) throw DataError(file, "", "file is unreadable");
    char buf[1 << 16];
    while (in.read(buf, sizeof buf), in.gcount() > 0) feed(std::string_view(buf, std::size_t(in.gcount())));
  }
  [[nodiscard]] std::string hex() const {
    char out[17];
    std::snprintf(out, sizeof out, "%016llx", static_cast<unsigned long long>(h_));
    return out;
  }

 private:
  std::uint64_t h_ = 0xcbf29ce484222325ull;
};

}  // namespace occsweep
