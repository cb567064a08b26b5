#pragma once
// Draws the marks of a view onto a rendered image (the annotated copy the agent receives next to
// the plain one): placement targets as translucent coloured regions with a circled number;
// items as a dot on the item joined by a leader line to a coloured disc with its number; overview
// labels as boxed l<N> keys. Deterministic: a fixed palette and a fixed label-placement order.

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "core/render/camera.h"
#include "core/render/mark_layout.h"
#include "core/render/marks.h"
#include "core/render/target_layout.h"

namespace mtg::render {

/// A copy of `image` (8-bit BGR, the camera's size) with `marks` drawn on it: the item marks as
/// `items` lays them out (mark_layout.h; they are not drawn without it), each `zooms` region
/// framed and labelled Z1, Z2, ... (where a zoomed view numbers what is crowded there).
/// Zoom frame k is named `zoom_names[k]` ("Z3": zooms are numbered across an observation's
/// pictures, depth first), zoom_name(k) where none is given.
/// Placement targets get their numbers where `targets` places them (layout_target_marks when none).
cv::Mat annotate(const cv::Mat& image, const Camera& camera, const Marks& marks, const MarkLayout* items = nullptr,
                 const std::vector<Eigen::AlignedBox2d>& zooms = {}, const std::vector<std::string>& zoom_names = {},
                 const TargetLayout* targets = nullptr);


/// Where the overview's labels go on the image: each label's box, clear of the others and inside
/// the image, and the projected anchor it points at (labels whose anchor is out of view are left
/// out). draw order = placement order = the labels' order, so the result is deterministic.
struct PlacedLabel {
  std::string text;
  cv::Point anchor;
  cv::Rect box;
};
std::vector<PlacedLabel> place_labels(const Camera& camera, const std::vector<LabelMark>& labels);

/// The colour of mark number `n` (1-based) in the fixed high-contrast palette, BGR.
cv::Scalar mark_colour(int n);

}  // namespace mtg::render
