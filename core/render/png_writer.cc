#include "core/render/png_writer.h"

#include <png.h>
#include <zlib.h>

#include <csetjmp>
#include <cstdio>
#include <string>

#include "core/util/error.h"

namespace mtg::render {
namespace {

void append(png_structp png, png_bytep data, png_size_t length) {
  auto* out = static_cast<std::vector<std::uint8_t>*>(png_get_io_ptr(png));
  out->insert(out->end(), data, data + length);
}

void flush(png_structp) {}

// libpng reports errors by longjmp to the png_jmpbuf of its caller; writes() holds only
// trivially destructible locals across that jump. Returns the libpng message, "" on success.
const char* writes(const cv::Mat& image, int colour, std::vector<std::uint8_t>& out) {
  static thread_local char message[256];
  message[0] = '\0';
  png_structp png = png_create_write_struct(
      PNG_LIBPNG_VER_STRING, nullptr,
      [](png_structp p, png_const_charp what) {
        std::snprintf(message, sizeof message, "%s", what);
        png_longjmp(p, 1);
      },
      nullptr);
  if (png == nullptr) return "png_create_write_struct failed";
  png_infop info = png_create_info_struct(png);
  if (info == nullptr || setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return message[0] != '\0' ? message : "png_create_info_struct failed";
  }
  png_set_write_fn(png, &out, append, flush);
  png_set_IHDR(png, info, static_cast<png_uint_32>(image.cols), static_cast<png_uint_32>(image.rows), 8, colour,
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_UP);
  png_set_compression_level(png, 1);
  png_set_compression_strategy(png, Z_RLE);
  png_write_info(png, info);
  if (image.channels() >= 3) png_set_bgr(png);  // OpenCV keeps blue first
  for (int r = 0; r < image.rows; ++r) png_write_row(png, image.ptr<png_byte>(r));
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return "";
}

}  // namespace

std::vector<std::uint8_t> encode_png(const cv::Mat& image) {
  int colour = 0;
  switch (image.type()) {
    case CV_8UC1: colour = PNG_COLOR_TYPE_GRAY; break;
    case CV_8UC3: colour = PNG_COLOR_TYPE_RGB; break;
    case CV_8UC4: colour = PNG_COLOR_TYPE_RGB_ALPHA; break;
    default:
      throw Error("png: cannot encode an image of OpenCV type " + std::to_string(image.type()) +
                  " (8-bit grey, BGR or BGRA only)");
  }
  std::vector<std::uint8_t> out;
  out.reserve(image.total() * image.elemSize() / 4);
  const char* failed = writes(image, colour, out);
  if (failed[0] != '\0') throw Error(std::string("png: ") + failed);
  return out;
}

}  // namespace mtg::render
