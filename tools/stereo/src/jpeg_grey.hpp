// Grey decoding of JPEG images (libjpeg), for the real stereo pairs of `dataset middlebury`.
#pragma once

#include <filesystem>
#include <string_view>

#include "occsweep/stereo/render.hpp"

namespace occsweep::stereo {

/// 8-bit luma of a baseline or progressive JPEG. DataError naming the file for a wrong signature, a corrupt
/// stream or more pixels than limits().image_pixels.
[[nodiscard]] GreyImage decodeJpegGrey(std::string_view bytes, const std::filesystem::path& file);

}  // namespace occsweep::stereo
