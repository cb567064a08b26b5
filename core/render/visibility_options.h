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
  // Calibrated by eye (docs/render.md, "Calibrated by eye"; tests/data/sight_labels): with these
  // the rule agrees with 97.8 % of the answers two people gave alike about 200 objects drawn from
  // the shipped apartments' views (it was 400 px and 60 %, which agreed with about half).
  double min_share = 0.25;  // of the object's own silhouette in that view
  int min_pixels = 40;      // image pixels showing the object, at least (under 1,600 the marked
                            // view adds a zoom where it shows at least twice as big)
  double min_gap = 10.0;   // image pixels between neighbours a rank or nearest/farthest counts

  int pass_width() const { return std::max(1, image_width / pass_scale); }
  int pass_height() const { return std::max(1, image_height / pass_scale); }
  nlohmann::json to_json() const;
};

}  // namespace mtg::render
