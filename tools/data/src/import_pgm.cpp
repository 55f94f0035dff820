// Netpbm greyscale depth (P5 binary, P2 ASCII): the format of slambook's Kinect frames.
#include <cctype>
#include <string>

#include "occsweep/io/bounded_read.hpp"
#include "occsweep/data/import_depth.hpp"
#include "occsweep/data/byte_reader.hpp"

namespace occsweep {
namespace {

// Header fields: whitespace-separated decimal numbers, `#` comments to the end of the line.
struct PgmHeader {
  std::string_view bytes;
  const std::filesystem::path& file;
  std::size_t pos = 2;

  std::uint64_t field(const char* name) {
    while (pos < bytes.size()) {
      if (std::isspace(static_cast<unsigned char>(bytes[pos]))) {
        ++pos;
      } else if (bytes[pos] == '#') {
        while (pos < bytes.size() && bytes[pos] != '\n') ++pos;
      } else {
        break;
      }
    }
    const std::size_t start = pos;
    while (pos < bytes.size() && std::isdigit(static_cast<unsigned char>(bytes[pos])) && pos - start < 12) ++pos;
    std::uint64_t v = 0;
    if (pos == start || !parseUnsigned(bytes.substr(start, pos - start), v) ||
        (pos < bytes.size() && !std::isspace(static_cast<unsigned char>(bytes[pos]))))
      throw DataError(file, std::string("header ") + name, "missing or not a decimal number");
    return v;
  }
};

}  // namespace

DepthImage decodePgm(std::string_view bytes, const std::filesystem::path& file) {
  if (bytes.size() < 2 || bytes[0] != 'P' || (bytes[1] != '5' && bytes[1] != '2'))
    throw DataError(file, "magic", "not a greyscale PGM: must start with P5 (binary) or P2 (ASCII)");
  const bool binary = bytes[1] == '5';
  PgmHeader h{bytes, file};
  const auto width = h.field("width"), height = h.field("height"), maxval = h.field("maxval");
  if (width == 0 || height == 0) throw DataError(file, "header", "width and height must be positive");
  if (saturatingProduct(width, height) > limits().image_pixels)
    throw DataError(file, "header", tooManyPixels(width, height));
  if (maxval == 0 || maxval > 65535) throw DataError(file, "header maxval", "must be 1..65535");
  DepthImage img;
  img.width = int(width);
  img.height = int(height);
  const std::uint64_t n = width * height;
  if (binary) {
    ++h.pos;  // exactly one whitespace byte ends the header
    const std::uint64_t bytes_per = maxval > 255 ? 2 : 1;
    const std::uint64_t have = bytes.size() - std::min(bytes.size(), h.pos);
    if (have < n * bytes_per)
      throw DataError(file, "raster", "holds " + std::to_string(have) + " bytes, expected " +
                                          std::to_string(n * bytes_per) + ": truncated file");
    if (have > n * bytes_per)
      throw DataError(file, "raster", std::to_string(have - n * bytes_per) +
                                          " bytes after the image: not a single PGM image");
    img.values.resize(n);
    const auto* p = reinterpret_cast<const unsigned char*>(bytes.data() + h.pos);
    for (std::uint64_t i = 0; i < n; ++i) {
      img.values[i] = bytes_per == 2 ? std::uint16_t(p[2 * i] << 8 | p[2 * i + 1]) : p[i];  // big-endian
      if (img.values[i] > maxval)
        throw DataError(file, "pixel " + std::to_string(i), "value " + std::to_string(img.values[i]) +
                                                                " is above maxval " + std::to_string(maxval));
    }
    return img;
  }
  // ASCII: each pixel needs at least two bytes, so a header claiming more than the file holds fails before
  // the raster is allocated.
  if (n > bytes.size() / 2 + 1)
    throw DataError(file, "raster", "header claims " + std::to_string(n) + " pixels, the file is too short");
  img.values.reserve(n);
  for (std::uint64_t i = 0; i < n; ++i) {
    const std::string where = "pixel " + std::to_string(i);
    const auto v = h.field(where.c_str());
    if (v > maxval) throw DataError(file, where, "value " + std::to_string(v) + " is above maxval");
    img.values.push_back(std::uint16_t(v));
  }
  return img;
}

DepthImage decodeDepthImage(std::string_view bytes, const std::filesystem::path& file) {
  if (bytes.size() >= 4 && static_cast<unsigned char>(bytes[0]) == 0x89 && bytes.substr(1, 3) == "PNG")
    return decodePng(bytes, file);
  if (bytes.size() >= 2 && bytes[0] == 'P') return decodePgm(bytes, file);
  throw DataError(file, "magic", "neither a PNG nor a PGM depth image");
}

DepthImage readDepthImage(const std::filesystem::path& file) {
  return decodeDepthImage(readFileBytes(file, std::uint64_t(1) << 31), file);
}

}  // namespace occsweep
