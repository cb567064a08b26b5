#include "core/render/image_codec.h"

#include <opencv2/imgcodecs.hpp>

#include "core/util/error.h"

namespace mtg::render {

std::vector<std::uint8_t> encode_image(const cv::Mat& image, const std::string& encoding) {
  std::vector<std::uint8_t> out;
  bool ok = false;
  if (encoding == "png") {
    // Level 1: rendered images have large flat areas, so the fastest level is already small.
    ok = cv::imencode(".png", image, out, {cv::IMWRITE_PNG_COMPRESSION, 1});
  } else if (encoding == "jpeg" || encoding == "jpg") {
    ok = cv::imencode(".jpg", image, out, {cv::IMWRITE_JPEG_QUALITY, 90});
  } else {
    throw Error("render: unknown encoding '" + encoding + "' (png or jpeg)");
  }
  if (!ok) throw Error("render: encoding a " + std::to_string(image.cols) + "x" + std::to_string(image.rows) +
                       " image as " + encoding + " failed");
  return out;
}

}  // namespace mtg::render
