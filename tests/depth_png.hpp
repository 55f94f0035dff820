// 16-bit greyscale PNG depth images written with libpng, as RGB-D recordings store them (docs/import.md): the
// synthetic recordings of the import tests. Link occsweep::data (which links libpng).
#pragma once

#include <catch2/catch.hpp>

#include <png.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <vector>

namespace occsweep::test {

/// A `width` x `height` image whose pixel (u, v) holds `raw(u, v)`.
inline void writeDepthPng(const std::filesystem::path& file, int width, int height,
                          const std::function<std::uint16_t(int u, int v)>& raw) {
  FILE* f = std::fopen(file.c_str(), "wb");
  REQUIRE(f);
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  png_init_io(png, f);
  png_set_IHDR(png, info, png_uint_32(width), png_uint_32(height), 16, PNG_COLOR_TYPE_GRAY, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  std::vector<png_byte> row(std::size_t(width) * 2);
  for (int v = 0; v < height; ++v) {
    for (int u = 0; u < width; ++u) {
      const std::uint16_t value = raw(u, v);
      row[std::size_t(2 * u)] = png_byte(value >> 8);  // PNG is big-endian
      row[std::size_t(2 * u + 1)] = png_byte(value & 0xff);
    }
    png_write_row(png, row.data());
  }
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  std::fclose(f);
}

}  // namespace occsweep::test
