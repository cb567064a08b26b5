#include "core/render/image_codec.h"

#include <opencv2/imgcodecs.hpp>

#include "core/render/png_writer.h"
#include "core/util/error.h"
#include "core/util/parallel.h"

namespace mtg::render {

void require_encoding(const std::string& encoding) {
  if (encoding != "png" && encoding != "jpeg" && encoding != "jpg") {
    throw Error("render: unknown encoding '" + encoding + "' (png or jpeg)");
  }
}

std::vector<std::uint8_t> encode_image(const cv::Mat& image, const std::string& encoding) {
  require_encoding(encoding);
  if (image.empty()) throw Error("render: an empty image cannot be encoded as " + encoding);
  std::vector<std::uint8_t> out;
  bool ok = false;
  if (encoding == "png") {
    out = encode_png(image);  // our settings (png_writer.h); OpenCV's filter choice is slow
    ok = !out.empty();
  } else {
    ok = cv::imencode(".jpg", image, out, {cv::IMWRITE_JPEG_QUALITY, 90});
  }
  if (!ok) throw Error("render: encoding a " + std::to_string(image.cols) + "x" + std::to_string(image.rows) +
                       " image as " + encoding + " failed");
  return out;
}

std::vector<std::vector<std::uint8_t>> encode_images(const std::vector<const cv::Mat*>& images,
                                                     const std::string& encoding, int jobs) {
  require_encoding(encoding);
  std::vector<std::vector<std::uint8_t>> out(images.size());
  parallel_for(images.size(), jobs, [&](std::size_t i) { out[i] = encode_image(*images[i], encoding); });
  return out;
}

}  // namespace mtg::render
