#include "core/render/target_layout.h"

#include <algorithm>
#include <cmath>

#include "core/render/disc_geometry.h"
#include "core/render/mark_layout.h"

namespace mtg::render {
namespace {

// A target's label point in the picture, when the picture shows it.
std::optional<Eigen::Vector2d> anchor_of(const Camera& camera, const RegionMark& r) {
  const auto at = camera.project(r.label_W);
  if (!at || at->x() < 0 || at->y() < 0 || at->x() >= camera.width || at->y() >= camera.height) return std::nullopt;
  return at;
}

}  // namespace

TargetLayout layout_target_marks(const Camera& camera, const std::vector<RegionMark>& regions) {
  TargetLayout out;
  out.radius = mark_style(camera.width, camera.height).radius;
  const double r = out.radius;
  struct Anchor {
    int number;
    Eigen::Vector2d at;
  };
  std::vector<Anchor> anchors;
  for (const RegionMark& m : regions) {
    if (const auto at = anchor_of(camera, m)) anchors.push_back({m.number, *at});
  }
  auto inside = [&](const Eigen::Vector2d& c) {
    return c.x() >= r + 1 && c.y() >= r + 1 && c.x() <= camera.width - r - 2 && c.y() <= camera.height - r - 2;
  };
  for (const Anchor& a : anchors) {
    // Another target's label point on this one's spot, nearer than half a disc (two free spaces
    // over the same gap between two objects), cannot be kept clear of: both number that place.
    auto elsewhere = [&](const Anchor& other) { return other.number != a.number && (other.at - a.at).norm() >= 0.5 * r; };
    auto fits = [&](const Eigen::Vector2d& c) {
      if (!inside(c)) return false;
      for (const Anchor& other : anchors) {  // no disc over another target's label point
        if (elsewhere(other) && (c - other.at).norm() < r + 3) return false;
      }
      for (const PlacedTarget& q : out.placed) {
        if ((c - q.disc).norm() < 2 * r + 2) return false;
        // Two lines from one spot may start under the first's disc, and meet only there.
        const bool same_spot = (q.anchor - a.at).norm() < 0.5 * r;
        if (!same_spot && distance_to_segment(q.disc, a.at, c) < r + 1) return false;
        if (distance_to_segment(c, q.anchor, q.disc) < r + 1) return false;
        if (!same_spot && segments_cross(a.at, c, q.anchor, q.disc)) return false;
      }
      for (const Anchor& other : anchors) {  // this line over another label point
        if (elsewhere(other) && distance_to_segment(other.at, a.at, c) < 4) return false;
      }
      return true;
    };
    std::optional<Eigen::Vector2d> chosen;
    if (fits(a.at)) chosen = a.at;
    if (!chosen) {
      for (const Eigen::Vector2d& c : disc_candidates(a.at, r)) {
        if (fits(c)) {
          chosen = c;
          break;
        }
      }
    }
    if (!chosen) {
      out.crowded.push_back(a.number);
      continue;
    }
    out.placed.push_back({a.number, a.at, *chosen});
  }
  return out;
}

std::vector<std::string> check_target_layout(const TargetLayout& layout, int width, int height) {
  std::vector<std::string> problems;
  const double r = layout.radius;
  auto name = [](const PlacedTarget& t) { return "target " + std::to_string(t.number); };
  for (std::size_t i = 0; i < layout.placed.size(); ++i) {
    const PlacedTarget& m = layout.placed[i];
    if (m.disc.x() < r || m.disc.y() < r || m.disc.x() > width - r || m.disc.y() > height - r) {
      problems.push_back(name(m) + ": its disc leaves the image");
    }
    for (std::size_t k = 0; k < layout.placed.size(); ++k) {
      if (k == i) continue;
      const PlacedTarget& q = layout.placed[k];
      if ((m.disc - q.anchor).norm() < r && (m.anchor - q.anchor).norm() >= 0.5 * r) {
        problems.push_back(name(m) + ": its disc covers the label point of " + name(q));
      }
      if (k > i && (m.disc - q.disc).norm() < 2 * r) problems.push_back(name(m) + " and " + name(q) + ": discs overlap");
      if (k > i && (m.anchor - q.anchor).norm() >= 0.5 * r && segments_cross(m.anchor, m.disc, q.anchor, q.disc)) {
        problems.push_back(name(m) + " and " + name(q) + ": leader lines cross");
      }
    }
  }
  return problems;
}

namespace {

// Zooms of the crowded targets of `layout` (a picture of `camera` numbering `regions`), appended
// depth first to `zooms`; their frames on the picture go to `frames`.
void add_target_zooms(const Camera& camera, const TargetLayout& layout, const std::vector<RegionMark>& regions,
                      int depth, std::vector<Eigen::AlignedBox2d>& frames, std::vector<std::size_t>& frame_zooms,
                      std::vector<TargetZoom>& zooms) {
  std::vector<ZoomPoint> points;
  for (const RegionMark& m : regions) {
    if (std::find(layout.crowded.begin(), layout.crowded.end(), m.number) == layout.crowded.end()) continue;
    if (const auto at = anchor_of(camera, m)) points.push_back({m.number, *at});
  }
  constexpr int kMaxZooms = 4;
  for (ZoomFrame& f : zoom_frames(camera, std::move(points), layout.radius, kMaxZooms - static_cast<int>(zooms.size()))) {
    if (zooms.size() >= static_cast<std::size_t>(kMaxZooms)) break;
    frames.push_back(f.region);
    const std::size_t slot = zooms.size();
    frame_zooms.push_back(slot);
    zooms.emplace_back();
    TargetZoom z;
    z.camera = f.camera;
    z.region = f.region;
    for (const RegionMark& m : regions) {
      const auto at = anchor_of(camera, m);
      const bool made_for = std::find(f.numbers.begin(), f.numbers.end(), m.number) != f.numbers.end();
      if (made_for || (at && f.region.contains(*at))) z.regions.push_back(m);
    }
    z.layout = layout_target_marks(z.camera, z.regions);
    if (depth > 1 && !z.layout.crowded.empty()) {
      add_target_zooms(z.camera, z.layout, z.regions, depth - 1, z.frames, z.frame_zooms, zooms);
    }
    zooms[slot] = std::move(z);
  }
}

}  // namespace

TargetMarksPlan plan_target_marks(const Camera& camera, const std::vector<RegionMark>& regions) {
  TargetMarksPlan plan;
  plan.camera = camera;
  plan.layout = layout_target_marks(camera, regions);
  if (!plan.layout.crowded.empty()) {
    add_target_zooms(camera, plan.layout, regions, /*depth=*/2, plan.frames, plan.frame_zooms, plan.zooms);
  }
  return plan;
}

bool TargetMarksPlan::placed(int number) const {
  auto in = [&](const TargetLayout& l) {
    return std::any_of(l.placed.begin(), l.placed.end(), [&](const PlacedTarget& p) { return p.number == number; });
  };
  return in(layout) || std::any_of(zooms.begin(), zooms.end(), [&](const TargetZoom& z) { return in(z.layout); });
}

std::vector<std::string> TargetMarksPlan::problems() const {
  std::vector<std::string> out;
  for (const std::string& p : check_target_layout(layout, camera.width, camera.height)) out.push_back("picture: " + p);
  for (std::size_t k = 0; k < zooms.size(); ++k) {
    for (const std::string& p : check_target_layout(zooms[k].layout, zooms[k].camera.width, zooms[k].camera.height)) {
      out.push_back(zoom_name(k) + ": " + p);
    }
  }
  return out;
}

}  // namespace mtg::render
