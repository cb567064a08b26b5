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

/// encode_image of every image, on up to `jobs` threads: an observation's images are encoded at
/// once (the bytes are the same on any number of threads). @throws as encode_image does, for the
/// first image that fails.
std::vector<std::vector<std::uint8_t>> encode_images(const std::vector<const cv::Mat*>& images,
                                                     const std::string& encoding, int jobs);

/// The PNG without its embedded colour profile (the iCCP chunk), the same pixels; anything that is
/// not a well-formed PNG comes back as it was. The dataset's textures carry profiles libpng
/// rejects with a warning on stderr for every texture decoded, and OpenCV applies no profile.
std::vector<std::uint8_t> without_color_profile(const std::vector<std::uint8_t>& png);

}  // namespace mtg::render
