#pragma once
// Encoded images for the bus and for files: PNG (lossless, fast settings) or JPEG.

#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace mtg::render {

/// @throws mtg::Error unless `encoding` is "png", "jpeg" or "jpg" (checked before any work).
void require_encoding(const std::string& encoding);

/// "png" or "jpeg" ("jpg" accepted). @throws mtg::Error for another encoding or a failed encode.
std::vector<std::uint8_t> encode_image(const cv::Mat& image, const std::string& encoding);

}  // namespace mtg::render
