#include "occsweep/io/bounded_read.hpp"

#include <fstream>
#include <utility>

namespace occsweep {

namespace fs = std::filesystem;

void requireRegularFile(const fs::path& file) {
  std::error_code ec;
  const auto status = fs::status(file, ec);  // follows links
  if (ec && ec != std::errc::no_such_file_or_directory)
    throw DataError(file, "", "cannot be opened: " + ec.message() + (ec == std::errc::too_many_symbolic_link_levels
                                                                        ? " (a symbolic link loop)"
                                                                        : ""));
  if (!fs::exists(status)) {
    const bool dangling = fs::is_symlink(fs::symlink_status(file, ec));
    throw DataError(file, "", dangling ? "is a symbolic link to a missing file" : "file is missing");
  }
  switch (status.type()) {
    case fs::file_type::regular: return;
    case fs::file_type::directory: throw DataError(file, "", "is a folder, expected a file");
    case fs::file_type::fifo: throw DataError(file, "", "is a FIFO (named pipe), expected a regular file");
    case fs::file_type::socket: throw DataError(file, "", "is a socket, expected a regular file");
    case fs::file_type::block:
    case fs::file_type::character: throw DataError(file, "", "is a device, expected a regular file");
    default: throw DataError(file, "", "is not a regular file");
  }
}

std::string readFileBytes(const fs::path& file, std::uint64_t max_bytes) {
  requireRegularFile(file);
  std::ifstream in(file, std::ios::binary);
  if (!in) throw DataError(file, "", "file is unreadable (permissions?)");
  std::string bytes;
  char buf[1 << 16];
  // Read in chunks rather than trusting file_size: pipes and /proc files report 0.
  while (in.read(buf, sizeof buf), in.gcount() > 0) {
    bytes.append(buf, std::size_t(in.gcount()));
    if (bytes.size() > max_bytes)
      throw DataError(file, "", "larger than " + std::to_string(max_bytes) + " bytes: refused");
  }
  if (in.bad()) throw DataError(file, "", "read error");
  return bytes;
}

std::optional<std::string> readFirstLine(const std::filesystem::path& file, std::size_t max_bytes) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(std::filesystem::status(file, ec))) return std::nullopt;  // a FIFO would wait
  std::ifstream in(file, std::ios::binary);
  std::string line;
  for (char ch; line.size() <= max_bytes && in.get(ch);) {
    if (ch == '\n') return line;
    line += ch;
  }
  return std::nullopt;
}

}  // namespace occsweep
