// libmtg_imgcodecs.so: the only code that links OpenCV's imgcodecs (core/render/codec_module.h
// loads it on first use). Plain C entry points, so dlsym finds them by name.

#include <cstddef>
#include <cstdint>
#include <exception>
#include <opencv2/imgcodecs.hpp>
#include <vector>

static_assert(cv::IMWRITE_JPEG_QUALITY == 1, "codec_module.h's kJpegQualityFlag");

extern "C" {

__attribute__((visibility("default"))) bool mtg_imgcodecs_decode_color(const std::uint8_t* data, std::size_t size,
                                                                       cv::Mat* out) {
  try {
    *out = cv::imdecode(cv::Mat(1, static_cast<int>(size), CV_8UC1, const_cast<std::uint8_t*>(data)), cv::IMREAD_COLOR);
    return true;
  } catch (const std::exception&) {
    *out = cv::Mat();
    return true;  // not an image OpenCV can read: empty, as imdecode's own refusal
  }
}

__attribute__((visibility("default"))) bool mtg_imgcodecs_encode(const char* extension, const cv::Mat* image,
                                                                 const std::vector<int>* params,
                                                                 std::vector<std::uint8_t>* out) {
  try {
    return cv::imencode(extension, *image, *out, *params);
  } catch (const std::exception&) {
    return false;
  }
}

}  // extern "C"
