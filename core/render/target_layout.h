#pragma once
// Where the number of each placement target (a free space or a cell of the 3x3 grid) goes in a
// marked image, by the rules item marks follow (mark_layout.h, disc_geometry.h): a disc sits on
// its target's label point, or beside it joined by a leader line; discs do not overlap, cover no
// other target's label point, stay inside the image, and leader lines neither cross nor run
// through another disc. A target whose number finds no such place is crowded: it is numbered in
// a zoomed view of its part of the picture (the same eye, a narrower lens), where the same rules
// hold, and a zoom of the zoom where it is still crowded. On a long counter with seventy free
// spaces the numbers would otherwise pile over one another (docs/render.md, "Free spaces a
// person can read").

#include <string>
#include <vector>

#include "core/render/camera.h"
#include "core/render/marks.h"

namespace mtg::render {

struct PlacedTarget {
  int number = 0;
  Eigen::Vector2d anchor = Eigen::Vector2d::Zero();  // the target's label point in the picture
  Eigen::Vector2d disc = Eigen::Vector2d::Zero();
};

struct TargetLayout {
  int radius = 13;
  std::vector<PlacedTarget> placed;
  std::vector<int> crowded;  // numbers left to a zoomed view
};

/// The layout of `regions` in a picture of `camera`; targets whose label point is outside the
/// picture are neither placed nor crowded (the picture does not show them).
TargetLayout layout_target_marks(const Camera& camera, const std::vector<RegionMark>& regions);

/// The rules above, checked on a finished layout: one line per broken rule.
std::vector<std::string> check_target_layout(const TargetLayout& layout, int width, int height);

struct TargetZoom {
  Camera camera;
  Eigen::AlignedBox2d region;         // in the first picture's pixels
  std::vector<RegionMark> regions;    // the targets it numbers: those it was made for and every
                                      // other whose label point lies in its region
  TargetLayout layout;
  std::vector<Eigen::AlignedBox2d> frames;  // its own zooms, framed on it
  std::vector<std::size_t> frame_zooms;     // each frame's zoom (index in TargetMarksPlan::zooms)
};

/// Every target numbered: in the picture, or in a zoom of its crowded part (two levels, four
/// zooms at most; what is still crowded then keeps the best place it has). Zooms are in the
/// order their images follow the picture (depth first).
struct TargetMarksPlan {
  Camera camera;
  TargetLayout layout;
  std::vector<Eigen::AlignedBox2d> frames;  // the picture's zooms, framed on it
  std::vector<std::size_t> frame_zooms;
  std::vector<TargetZoom> zooms;
  /// Whether target `number` has a readable place in the picture or a zoom.
  bool placed(int number) const;
  /// Every broken rule of every layout, "<picture>: <problem>".
  std::vector<std::string> problems() const;
};

TargetMarksPlan plan_target_marks(const Camera& camera, const std::vector<RegionMark>& regions);

}  // namespace mtg::render
