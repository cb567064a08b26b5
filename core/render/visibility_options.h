#pragma once
// The thresholds of "clearly visible" (visibility.h), kept apart so that task options can hold
// them without the renderer's headers.

#include <algorithm>
#include <nlohmann/json.hpp>

namespace mtg::render {

struct VisibilityOptions {
  int image_width = 640;   // the image the agent gets; the pixel thresholds are in its pixels
  int image_height = 480;
  int pass_scale = 2;      // the id pass is this many times smaller along each axis
  double min_share = 0.6;  // of the object's own silhouette in that view
  int min_pixels = 400;    // image pixels showing the object, at least (about 20 x 20; under 1,600
                           // the marked view adds a zoom where it shows at least twice as big)
  double min_gap = 10.0;   // image pixels between neighbours a rank or nearest/farthest counts

  int pass_width() const { return std::max(1, image_width / pass_scale); }
  int pass_height() const { return std::max(1, image_height / pass_scale); }
  nlohmann::json to_json() const;
};

}  // namespace mtg::render
