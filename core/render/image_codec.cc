#include "core/render/image_codec.h"

#include <algorithm>

#include "core/render/codec_module.h"
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
    ok = encode_with_imgcodecs(".jpg", image, out, {kJpegQualityFlag, 90});
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

std::vector<std::uint8_t> without_color_profile(const std::vector<std::uint8_t>& png) {
  static constexpr std::uint8_t kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (png.size() < 8 || !std::equal(kSignature, kSignature + 8, png.begin())) return png;
  std::vector<std::uint8_t> out(png.begin(), png.begin() + 8);
  out.reserve(png.size());
  std::size_t at = 8;
  while (at + 12 <= png.size()) {  // length (4), type (4), data, CRC (4)
    const std::size_t length = (std::size_t{png[at]} << 24) | (std::size_t{png[at + 1]} << 16) |
                               (std::size_t{png[at + 2]} << 8) | std::size_t{png[at + 3]};
    if (length > png.size() - at - 12) return png;  // torn: leave it to the decoder to judge
    const std::string type(png.begin() + static_cast<std::ptrdiff_t>(at + 4), png.begin() + static_cast<std::ptrdiff_t>(at + 8));
    const std::size_t end = at + 12 + length;
    if (type != "iCCP") {
      out.insert(out.end(), png.begin() + static_cast<std::ptrdiff_t>(at), png.begin() + static_cast<std::ptrdiff_t>(end));
    }
    at = end;
    if (type == "IEND") break;
  }
  return at == png.size() ? out : png;
}

}  // namespace mtg::render
