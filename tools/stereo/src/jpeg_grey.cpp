// Grey decoding of a JPEG through libjpeg (the Middlebury pair OpenCV ships is JPEG): libjpeg's own colour
// conversion to luma, Y = 0.299 R + 0.587 G + 0.114 B, as OpenCV's IMREAD_GRAYSCALE.
#include "jpeg_grey.hpp"

#include <csetjmp>
#include <cstdio>

#include <jpeglib.h>

#include "occsweep/io/data_error.hpp"
#include "occsweep/data/import_depth.hpp"

namespace occsweep::stereo {
namespace {

struct JpegError {
  jpeg_error_mgr mgr;
  std::jmp_buf jump;
  char message[JMSG_LENGTH_MAX] = {0};
};

void onError(j_common_ptr info) {
  auto* err = reinterpret_cast<JpegError*>(info->err);
  info->err->format_message(info, err->message);
  std::longjmp(err->jump, 1);
}

// Only C objects and the caller's plain buffer live in this frame: safe for setjmp/longjmp. False on failure.
bool decode(std::string_view bytes, GreyImage& out, JpegError& err, bool& too_big) {
  jpeg_decompress_struct info;
  info.err = jpeg_std_error(&err.mgr);
  err.mgr.error_exit = onError;
  if (setjmp(err.jump)) {
    jpeg_destroy_decompress(&info);
    return false;
  }
  jpeg_create_decompress(&info);
  jpeg_mem_src(&info, reinterpret_cast<const unsigned char*>(bytes.data()), static_cast<unsigned long>(bytes.size()));
  jpeg_read_header(&info, TRUE);
  if (std::uint64_t(info.image_width) * info.image_height > limits().image_pixels) {
    too_big = true;
    out.width = int(info.image_width), out.height = int(info.image_height);
    jpeg_destroy_decompress(&info);
    return false;
  }
  info.out_color_space = JCS_GRAYSCALE;
  jpeg_start_decompress(&info);
  out.width = int(info.output_width);
  out.height = int(info.output_height);
  out.pixels.resize(std::size_t(out.width) * out.height);
  while (info.output_scanline < info.output_height) {
    JSAMPROW row = out.pixels.data() + std::size_t(info.output_scanline) * out.width;
    jpeg_read_scanlines(&info, &row, 1);
  }
  jpeg_finish_decompress(&info);
  jpeg_destroy_decompress(&info);
  return true;
}

}  // namespace

GreyImage decodeJpegGrey(std::string_view bytes, const std::filesystem::path& file) {
  if (bytes.size() < 3 || static_cast<unsigned char>(bytes[0]) != 0xFF || static_cast<unsigned char>(bytes[1]) != 0xD8)
    throw DataError(file, "signature", "not a JPEG file (wrong magic bytes)");
  GreyImage image;
  JpegError err;
  bool too_big = false;
  if (!decode(bytes, image, err, too_big)) {
    if (too_big) throw DataError(file, "header", tooManyPixels(std::uint64_t(image.width), std::uint64_t(image.height)));
    throw DataError(file, "", std::string("corrupt JPEG: ") + err.message);
  }
  return image;
}

}  // namespace occsweep::stereo
