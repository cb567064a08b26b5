#pragma once
// PNG encoding with libpng directly, for the settings OpenCV 4.6 does not expose: one cheap
// row filter (Up) instead of libpng's adaptive choice, which tries all five per row and was
// over half of an observation's encoding time; zlib level 1 with run-length matching. On
// apt_0's 640x480 views: two PNGs in 8.9 ms instead of 23.6, 246 KiB instead of 236. No filter
// at all made files 3.4x larger and slower to deflate; Sub was 12.9 ms (docs/render.md).

#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

namespace mtg::render {

/// A lossless PNG of an 8-bit grey, BGR or BGRA image. @throws mtg::Error on another type or
/// a libpng failure.
std::vector<std::uint8_t> encode_png(const cv::Mat& image);

}  // namespace mtg::render
