#pragma once
// OpenCV's image codecs (imgcodecs), loaded when an image is first decoded or encoded as JPEG, from
// libmtg_imgcodecs.so beside the program (core/render/codec_module_impl.cc). Linked in, imgcodecs
// brings 139 shared libraries (GDAL, GDCM, libde265, HDF5, ...) into every process at start: most
// of what `mtg --help` cost (80 ms of CPU, 64 MiB) and half a task run's memory, for commands that
// never touch an image (issue 56). PNG writing goes through libpng directly (png_writer.h).

#include <cstdint>
#include <opencv2/core.hpp>
#include <span>
#include <string>
#include <vector>

namespace mtg::render {

/// cv::imdecode(bytes, cv::IMREAD_COLOR): 8-bit BGR; empty when the bytes are not an image.
/// @throws mtg::Error naming the module when it cannot be loaded.
cv::Mat decode_color_image(std::span<const std::uint8_t> bytes);

/// cv::imencode(extension, image, out, params) with `params` as imgcodecs' flag pairs; false when
/// the encoder refuses. @throws mtg::Error naming the module when it cannot be loaded.
bool encode_with_imgcodecs(const std::string& extension, const cv::Mat& image, std::vector<std::uint8_t>& out,
                           const std::vector<int>& params = {});

/// imgcodecs' flag for JPEG quality (cv::IMWRITE_JPEG_QUALITY), without its header.
inline constexpr int kJpegQualityFlag = 1;

/// Whether OpenCV's imgcodecs is mapped into this process (/proc/self/maps): for the tests that
/// check a command that touches no image never loads it.
bool imgcodecs_loaded();

}  // namespace mtg::render
