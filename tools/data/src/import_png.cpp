// PNG depth through libpng (Debian's libpng 1.6), never a hand-written inflater.
#include <csetjmp>
#include <cstring>
#include <string>

#include <png.h>

#include "occsweep/io/data_error.hpp"
#include "occsweep/data/import_depth.hpp"

namespace occsweep {
namespace {

// State shared with libpng's C callbacks; owned by decodePng so that longjmp skips no C++ destructor.
struct PngJob {
  std::string_view bytes;
  std::size_t pos = 0;
  char error[256] = {0};
  png_uint_32 width = 0, height = 0;
  int bit_depth = 0, color_type = 0, interlace = 0;
  std::vector<png_bytep>* rows = nullptr;
  std::vector<unsigned char>* raw = nullptr;
  bool too_big = false, wrong_type = false;
};

void readCallback(png_structp png, png_bytep data, png_size_t length) {
  auto* job = static_cast<PngJob*>(png_get_io_ptr(png));
  if (length > job->bytes.size() - job->pos) png_error(png, "truncated file: the stream ends early");
  std::memcpy(data, job->bytes.data() + job->pos, length);
  job->pos += length;
}

void errorCallback(png_structp png, png_const_charp message) {
  auto* job = static_cast<PngJob*>(png_get_error_ptr(png));
  std::snprintf(job->error, sizeof job->error, "%s", message);
  png_longjmp(png, 1);
}

void warningCallback(png_structp, png_const_charp) {}  // ancillary-chunk warnings do not change the depth

// Only C objects live in this frame: safe for setjmp/longjmp. Returns false with job.error set on failure.
bool decodeRaw(PngJob& job) {
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &job, errorCallback, warningCallback);
  if (!png) return std::snprintf(job.error, sizeof job.error, "libpng: out of memory"), false;
  png_infop info = png_create_info_struct(png);
  if (!info || setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, info ? &info : nullptr, nullptr);
    if (!job.error[0]) std::snprintf(job.error, sizeof job.error, "libpng: out of memory");
    return false;
  }
  png_set_read_fn(png, &job, readCallback);
  png_set_user_limits(png, 1u << 16, 1u << 16);
  png_set_chunk_malloc_max(png, 64u << 20);
  png_read_info(png, info);
  png_get_IHDR(png, info, &job.width, &job.height, &job.bit_depth, &job.color_type, &job.interlace, nullptr, nullptr);
  if (std::uint64_t(job.width) * job.height > limits().image_pixels) {
    job.too_big = true;
    png_destroy_read_struct(&png, &info, nullptr);
    return false;
  }
  if (job.color_type != PNG_COLOR_TYPE_GRAY || (job.bit_depth != 16 && job.bit_depth != 8)) {
    job.wrong_type = true;
    png_destroy_read_struct(&png, &info, nullptr);
    return false;
  }
  if (job.bit_depth == 16) png_set_swap(png);  // PNG stores big-endian; we want host (little-endian) words
  png_set_interlace_handling(png);
  png_read_update_info(png, info);
  const std::size_t row_bytes = png_get_rowbytes(png, info);
  job.raw->resize(row_bytes * job.height);
  job.rows->resize(job.height);
  for (png_uint_32 r = 0; r < job.height; ++r) (*job.rows)[r] = job.raw->data() + r * row_bytes;
  png_read_image(png, job.rows->data());
  png_read_end(png, nullptr);
  png_destroy_read_struct(&png, &info, nullptr);
  return true;
}

}  // namespace

DepthImage decodePng(std::string_view bytes, const std::filesystem::path& file) {
  if (bytes.size() < 8 || png_sig_cmp(reinterpret_cast<png_const_bytep>(bytes.data()), 0, 8) != 0)
    throw DataError(file, "signature", "not a PNG file (wrong magic bytes)");
  std::vector<png_bytep> rows;
  std::vector<unsigned char> raw;
  PngJob job;
  job.bytes = bytes;
  job.rows = &rows;
  job.raw = &raw;
  if (!decodeRaw(job)) {
    if (job.too_big)
      throw DataError(file, "header", tooManyPixels(job.width, job.height));
    if (job.wrong_type)
      throw DataError(file, "header", "colour type " + std::to_string(job.color_type) + ", bit depth " +
                                          std::to_string(job.bit_depth) +
                                          ": a depth image must be 8- or 16-bit greyscale without alpha");
    throw DataError(file, "", std::string("corrupt PNG: ") + job.error);
  }
  DepthImage img;
  img.width = int(job.width);
  img.height = int(job.height);
  img.values.resize(std::size_t(job.width) * job.height);
  if (job.bit_depth == 16) {
    std::memcpy(img.values.data(), raw.data(), img.values.size() * 2);
  } else {
    for (std::size_t i = 0; i < img.values.size(); ++i) img.values[i] = raw[i];
  }
  return img;
}

}  // namespace occsweep
