#include "core/render/overlay.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

namespace mtg::render {
namespace {

// 24 colours that stay distinct on wood, white and grey surfaces (RGB, converted to BGR below).
constexpr std::array<std::array<int, 3>, 24> kPalette = {{
    {230, 25, 75},  {60, 180, 75},   {0, 130, 200},  {245, 130, 48}, {145, 30, 180}, {70, 240, 240},
    {240, 50, 230}, {210, 245, 60},  {250, 190, 212}, {0, 128, 128}, {220, 190, 255}, {170, 110, 40},
    {255, 225, 25}, {128, 0, 0},     {170, 255, 195}, {128, 128, 0}, {255, 215, 180}, {0, 0, 128},
    {255, 99, 71},  {46, 139, 87},   {65, 105, 225}, {255, 140, 0},  {199, 21, 133}, {32, 178, 170},
}};

cv::Point to_cv(const Eigen::Vector2d& p) {
  return {static_cast<int>(std::lround(p.x())), static_cast<int>(std::lround(p.y()))};
}

// Black or white, whichever reads better on `c`.
cv::Scalar ink_on(const cv::Scalar& c) {
  const double luma = 0.114 * c[0] + 0.587 * c[1] + 0.299 * c[2];
  return luma > 150 ? cv::Scalar(0, 0, 0) : cv::Scalar(255, 255, 255);
}

struct Style {
  int radius;        // label disc
  double font;       // cv::putText scale
  int thickness;
};

Style style_for(int width, int height) {
  const double s = std::min(width, height) / 480.0;
  return {std::max(9, static_cast<int>(std::lround(13 * s))), 0.5 * s, std::max(1, static_cast<int>(std::lround(1.6 * s)))};
}

void centred_text(cv::Mat& image, const std::string& text, cv::Point at, const Style& st, const cv::Scalar& ink) {
  int baseline = 0;
  const cv::Size size = cv::getTextSize(text, cv::FONT_HERSHEY_SIMPLEX, st.font, st.thickness, &baseline);
  cv::putText(image, text, {at.x - size.width / 2, at.y + size.height / 2}, cv::FONT_HERSHEY_SIMPLEX, st.font, ink,
              st.thickness, cv::LINE_AA);
}


struct Disc {
  int number;
  cv::Point anchor, label;
  cv::Scalar fill, ink;
};

// Leader lines first, so no line crosses a disc drawn earlier; then the discs.
void draw_discs(cv::Mat& image, const std::vector<Disc>& discs, const Style& st) {
  for (const Disc& d : discs) {
    if (d.anchor == d.label) continue;
    cv::line(image, d.anchor, d.label, cv::Scalar(0, 0, 0), st.thickness + 2, cv::LINE_AA);
    cv::line(image, d.anchor, d.label, mark_colour(d.number), st.thickness, cv::LINE_AA);
  }
  for (const Disc& d : discs) {
    cv::circle(image, d.label, st.radius + 1, cv::Scalar(0, 0, 0), cv::FILLED, cv::LINE_AA);
    cv::circle(image, d.label, st.radius, d.fill, cv::FILLED, cv::LINE_AA);
    centred_text(image, std::to_string(d.number), d.label, st, d.ink);
  }
}

// Targets: translucent regions in their colour, a white disc with the black key where the layout
// placed it (target_layout.h); a crowded target is tinted here and numbered in its zoom.
void draw_regions(cv::Mat& image, const Camera& camera, const std::vector<RegionMark>& regions, const Style& st,
                  const TargetLayout& layout) {
  cv::Mat tint = image.clone();
  std::vector<Disc> discs;
  for (const RegionMark& r : regions) {
    std::vector<std::vector<cv::Point>> polys;
    bool visible = true;
    for (const auto& ring : r.rings_W) {
      std::vector<cv::Point> poly;
      for (const auto& p : ring) {
        const auto q = camera.project(p);
        if (!q) visible = false;
        else poly.push_back(to_cv(*q));
      }
      polys.push_back(std::move(poly));
    }
    if (!visible) continue;  // a region behind the camera is not drawn at all
    cv::fillPoly(tint, polys, mark_colour(r.number), cv::LINE_AA);
    cv::polylines(image, polys, true, mark_colour(r.number), st.thickness, cv::LINE_AA);
    const auto placed = std::find_if(layout.placed.begin(), layout.placed.end(),
                                     [&](const PlacedTarget& t) { return t.number == r.number; });
    if (placed == layout.placed.end()) continue;
    discs.push_back({r.number, to_cv(placed->anchor), to_cv(placed->disc), cv::Scalar(255, 255, 255),
                     cv::Scalar(0, 0, 0)});
  }
  cv::addWeighted(tint, 0.5, image, 0.5, 0.0, image);
  draw_discs(image, discs, st);
}

// Items as their layout places them: leader lines first (each outlined in black), then the dots,
// then the discs; a disc on its own object needs neither line nor dot. An object that does not
// show gets a grey disc: its number exists, but there is nothing to see of it from here.
void draw_items(cv::Mat& image, const MarkLayout& layout) {
  const MarkStyle& st = layout.style;
  for (const PlacedMark& m : layout.placed) {
    if (m.on_object()) continue;
    cv::line(image, to_cv(m.anchor), to_cv(m.disc), cv::Scalar(0, 0, 0), st.thickness + 2, cv::LINE_AA);
    cv::line(image, to_cv(m.anchor), to_cv(m.disc), mark_colour(m.number), st.thickness, cv::LINE_AA);
  }
  for (const PlacedMark& m : layout.placed) {
    if (m.on_object()) continue;
    cv::circle(image, to_cv(m.anchor), st.dot_radius, cv::Scalar(0, 0, 0), cv::FILLED, cv::LINE_AA);
    cv::circle(image, to_cv(m.anchor), std::max(1, st.dot_radius - 1), mark_colour(m.number), cv::FILLED, cv::LINE_AA);
  }
  const Style text{st.radius, st.font, st.thickness};
  for (const PlacedMark& m : layout.placed) {
    const cv::Scalar fill = m.visible ? mark_colour(m.number) : cv::Scalar(150, 150, 150);
    cv::circle(image, to_cv(m.disc), st.radius + 1, cv::Scalar(0, 0, 0), cv::FILLED, cv::LINE_AA);
    cv::circle(image, to_cv(m.disc), st.radius, fill, cv::FILLED, cv::LINE_AA);
    centred_text(image, std::to_string(m.number), to_cv(m.disc), text, ink_on(fill));
  }
}

// A zoomed view's region: a white frame outlined in black, its name in a box at the top left.
void draw_zoom_frames(cv::Mat& image, const std::vector<Eigen::AlignedBox2d>& zooms,
                      const std::vector<std::string>& names, const Style& st) {
  for (std::size_t k = 0; k < zooms.size(); ++k) {
    const cv::Rect box(to_cv(zooms[k].min()), to_cv(zooms[k].max()));
    cv::rectangle(image, box, cv::Scalar(0, 0, 0), 3, cv::LINE_AA);
    cv::rectangle(image, box, cv::Scalar(255, 255, 255), 1, cv::LINE_AA);
    const std::string name = k < names.size() ? names[k] : zoom_name(k);
    int baseline = 0;
    const cv::Size size = cv::getTextSize(name, cv::FONT_HERSHEY_SIMPLEX, st.font, st.thickness, &baseline);
    const cv::Rect tag(box.x + 2, box.y + 2, size.width + 6, size.height + 6);
    cv::rectangle(image, tag, cv::Scalar(255, 255, 255), cv::FILLED);
    cv::rectangle(image, tag, cv::Scalar(0, 0, 0), 1);
    centred_text(image, name, {tag.x + tag.width / 2, tag.y + tag.height / 2}, st, cv::Scalar(0, 0, 0));
  }
}

// Overview labels never cover each other: each tries its anchor, then points on rings around it
// (8 directions on the first rings, 16 farther out), and keeps the first box that is inside the
// image and clear of the labels already placed. A label moved off its anchor gets a dot on the
// anchor and a leader line, so stacked platforms (shelves, cabinet levels) each get a readable
// label pointing at the same place. Deterministic: labels are placed in their order (l1, l2, ...).
// `keep_clear`: boxes no label may touch (the discs of a placing view's targets).
std::vector<PlacedLabel> place_labels(const Camera& camera, const std::vector<LabelMark>& labels, const Style& st,
                                      const std::vector<cv::Rect>& keep_clear = {}) {
  const cv::Rect frame(0, 0, camera.width, camera.height);
  std::vector<PlacedLabel> placed;
  auto clear = [&](const cv::Rect& box) {
    if ((box & frame) != box) return false;
    const cv::Rect padded(box.x - 1, box.y - 1, box.width + 2, box.height + 2);
    return std::none_of(placed.begin(), placed.end(), [&](const PlacedLabel& p) { return (p.box & padded).area() > 0; }) &&
           std::none_of(keep_clear.begin(), keep_clear.end(), [&](const cv::Rect& r) { return (r & padded).area() > 0; });
  };
  constexpr int kRings = 14;
  for (const LabelMark& l : labels) {
    const auto at = camera.project(l.anchor_W);
    if (!at || !frame.contains(to_cv(*at))) continue;
    int baseline = 0;
    const cv::Size size = cv::getTextSize(l.text, cv::FONT_HERSHEY_SIMPLEX, st.font, st.thickness, &baseline);
    const cv::Point anchor = to_cv(*at);
    const cv::Size box_size(size.width + 6, size.height + 6);
    auto box_at = [&](cv::Point c) {
      return cv::Rect(c.x - box_size.width / 2, c.y - box_size.height / 2, box_size.width, box_size.height);
    };
    std::optional<cv::Rect> chosen;
    for (int ring = 0; ring <= kRings && !chosen; ++ring) {
      const int directions = ring == 0 ? 1 : (ring < 4 ? 8 : 16);
      const double step = box_size.height + 2.0;
      for (int d = 0; d < directions && !chosen; ++d) {
        // Up first (labels above their platform read best), then clockwise.
        const double angle = -M_PI / 2 + 2 * M_PI * d / directions;
        const cv::Point c(anchor.x + static_cast<int>(std::lround(std::cos(angle) * ring * step * 1.4)),
                          anchor.y + static_cast<int>(std::lround(std::sin(angle) * ring * step)));
        if (clear(box_at(c))) chosen = box_at(c);
      }
    }
    placed.push_back({l.text, anchor, chosen.value_or(box_at(anchor))});
  }
  return placed;
}

// The leader of each label moved off its anchor: a line from the anchor to the box's nearest
// point, and a dot on the anchor (`ringed`: white around the black, as on dark scenery).
void draw_leaders(cv::Mat& image, const std::vector<PlacedLabel>& placed, bool ringed) {
  const cv::Scalar black(0, 0, 0), white(255, 255, 255);
  for (const PlacedLabel& p : placed) {
    if (p.box.contains(p.anchor)) continue;
    const cv::Point near(std::clamp(p.anchor.x, p.box.x, p.box.x + p.box.width - 1),
                         std::clamp(p.anchor.y, p.box.y, p.box.y + p.box.height - 1));
    cv::line(image, p.anchor, near, white, 3, cv::LINE_AA);
    cv::line(image, p.anchor, near, black, 1, cv::LINE_AA);
    if (ringed) cv::circle(image, p.anchor, 3, white, cv::FILLED, cv::LINE_AA);
    cv::circle(image, p.anchor, ringed ? 2 : 3, black, cv::FILLED, cv::LINE_AA);
  }
}

void draw_labels(cv::Mat& image, const Camera& camera, const std::vector<LabelMark>& labels, const Style& st) {
  const std::vector<PlacedLabel> placed = place_labels(camera, labels, st);
  const cv::Scalar black(0, 0, 0), white(255, 255, 255);
  draw_leaders(image, placed, /*ringed=*/false);
  for (const PlacedLabel& p : placed) {
    cv::rectangle(image, p.box, white, cv::FILLED);
    cv::rectangle(image, p.box, black, 1);
    centred_text(image, p.text, {p.box.x + p.box.width / 2, p.box.y + p.box.height / 2}, st, black);
  }
}

// Lettered scenery of a placing view: a black box with a white letter, unlike every other mark
// (numbers are discs, l<N> white boxes), placed as labels are but clear of the targets' discs and
// of the points they number; one moved off its object points at it with a dot and a line.
void draw_fixtures(cv::Mat& image, const Camera& camera, const std::vector<LabelMark>& fixtures, const Style& st,
                   const TargetLayout& targets) {
  std::vector<cv::Rect> keep_clear;
  const int r = targets.radius + 2;
  for (const PlacedTarget& t : targets.placed) {
    const cv::Point disc = to_cv(t.disc), anchor = to_cv(t.anchor);
    keep_clear.emplace_back(disc.x - r, disc.y - r, 2 * r + 1, 2 * r + 1);
    keep_clear.emplace_back(anchor.x - 3, anchor.y - 3, 7, 7);
  }
  const std::vector<PlacedLabel> placed = place_labels(camera, fixtures, st, keep_clear);
  const cv::Scalar black(0, 0, 0), white(255, 255, 255);
  draw_leaders(image, placed, /*ringed=*/true);
  for (const PlacedLabel& p : placed) {
    cv::rectangle(image, p.box, white, cv::FILLED);
    cv::rectangle(image, cv::Rect(p.box.x + 1, p.box.y + 1, p.box.width - 2, p.box.height - 2), black, cv::FILLED);
    centred_text(image, p.text, {p.box.x + p.box.width / 2, p.box.y + p.box.height / 2}, st, white);
  }
}

}  // namespace

std::vector<PlacedLabel> place_labels(const Camera& camera, const std::vector<LabelMark>& labels) {
  return place_labels(camera, labels, style_for(camera.width, camera.height));
}

cv::Scalar mark_colour(int n) {
  const auto& c = kPalette[static_cast<std::size_t>(std::max(0, n - 1)) % kPalette.size()];
  return cv::Scalar(c[2], c[1], c[0]);
}

cv::Mat annotate(const cv::Mat& image, const Camera& camera, const Marks& marks, const MarkLayout* items,
                 const std::vector<Eigen::AlignedBox2d>& zooms, const std::vector<std::string>& zoom_names,
                 const TargetLayout* targets) {
  cv::Mat out = image.clone();
  const Style st = style_for(out.cols, out.rows);
  const TargetLayout target_layout =
      targets != nullptr || marks.regions.empty() ? TargetLayout{} : layout_target_marks(camera, marks.regions);
  const TargetLayout& laid = targets != nullptr ? *targets : target_layout;
  if (!marks.regions.empty()) draw_regions(out, camera, marks.regions, st, laid);
  if (!zooms.empty()) draw_zoom_frames(out, zooms, zoom_names, st);
  if (!marks.fixtures.empty()) draw_fixtures(out, camera, marks.fixtures, st, laid);
  if (items != nullptr) draw_items(out, *items);
  if (!marks.labels.empty()) draw_labels(out, camera, marks.labels, st);
  return out;
}

}  // namespace mtg::render
