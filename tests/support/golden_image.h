#pragma once
// Golden images with a tolerance: rasterisers differ in the last bit of an edge or a texture
// sample (llvmpipe versions, a real GPU), so images are compared pixel by pixel with a threshold.
// On a mismatch the actual image and a diff image (differing pixels in red over a grey copy)
// are written to the temp folder and named in the message. MTG_UPDATE_GOLDEN=1 rewrites goldens.

#include <opencv2/core.hpp>
#include <string>

namespace mtg::testing {

struct ImageTolerance {
  int channel = 40;               // a pixel differs when a channel differs by more than this
  double max_share = 0.01;        // ... and at most this share of pixels may differ
};

/// Returns "" when `actual` matches tests/golden/<name> within `tolerance`, else a message.
std::string compare_golden_image(const std::string& name, const cv::Mat& actual, ImageTolerance tolerance = {});

}  // namespace mtg::testing
