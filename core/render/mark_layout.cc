#include "core/render/mark_layout.h"

#include "core/render/disc_geometry.h"
#include "core/render/visibility.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <optional>
#include <opencv2/imgproc.hpp>

namespace mtg::render {
namespace {

constexpr double kOwnShare = 0.7;  // a disc sits on its object when the object holds this much of it

// The pixels of the numbered objects in the pass: how many each has, and their bounding rect.
struct Pixels {
  int count = 0;
  int u0 = 0, v0 = 0, u1 = -1, v1 = -1;  // inclusive
};

std::map<std::int32_t, Pixels> pixels_of(const IdImage& ids, const std::vector<ItemMark>& items) {
  std::int32_t top = -1;
  for (const ItemMark& m : items) top = std::max(top, static_cast<std::int32_t>(m.object.index()));
  std::vector<Pixels> table(static_cast<std::size_t>(top + 1));
  std::vector<bool> numbered(table.size(), false);
  for (const ItemMark& m : items) numbered[m.object.index()] = true;
  for (int v = 0; v < ids.height; ++v) {
    for (int u = 0; u < ids.width; ++u) {
      const std::int32_t id = ids.at(u, v);
      if (id < 0 || id > top || !numbered[static_cast<std::size_t>(id)]) continue;
      Pixels& p = table[static_cast<std::size_t>(id)];
      if (p.count++ == 0) {
        p.u0 = p.u1 = u;
        p.v0 = p.v1 = v;
      }
      p.u0 = std::min(p.u0, u);
      p.u1 = std::max(p.u1, u);
      p.v0 = std::min(p.v0, v);
      p.v1 = std::max(p.v1, v);
    }
  }
  std::map<std::int32_t, Pixels> out;
  for (const ItemMark& m : items) out[static_cast<std::int32_t>(m.object.index())] = table[m.object.index()];
  return out;
}

// The pass pixel deepest inside the object's pixels (first in row order among equals), as an
// image point at that pixel's centre.
Eigen::Vector2d deepest_pixel(const IdImage& ids, int scale, std::int32_t id, const Pixels& px) {
  const int w = px.u1 - px.u0 + 3, h = px.v1 - px.v0 + 3;  // a background border all round
  cv::Mat mask(h, w, CV_8UC1, cv::Scalar(0));
  for (int v = px.v0; v <= px.v1; ++v) {
    for (int u = px.u0; u <= px.u1; ++u) {
      if (ids.at(u, v) == id) mask.at<std::uint8_t>(v - px.v0 + 1, u - px.u0 + 1) = 255;
    }
  }
  cv::Mat dist;
  cv::distanceTransform(mask, dist, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  float best = -1.0f;
  int bu = 0, bv = 0;
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      const float d = dist.at<float>(v, u);
      if (d > best) {
        best = d;
        bu = u;
        bv = v;
      }
    }
  }
  return {(bu - 1 + px.u0 + 0.5) * scale, (bv - 1 + px.v0 + 0.5) * scale};
}

// Pass pixels whose centre lies within the disc, counted per object id (sorted by id).
std::vector<std::pair<std::int32_t, int>> under_disc(const IdImage& ids, int scale, const Eigen::Vector2d& c, double r) {
  std::vector<std::pair<std::int32_t, int>> out;
  const double s = scale;
  const int u0 = std::max(0, static_cast<int>(std::floor((c.x() - r) / s)));
  const int u1 = std::min(ids.width - 1, static_cast<int>(std::ceil((c.x() + r) / s)));
  const int v0 = std::max(0, static_cast<int>(std::floor((c.y() - r) / s)));
  const int v1 = std::min(ids.height - 1, static_cast<int>(std::ceil((c.y() + r) / s)));
  for (int v = v0; v <= v1; ++v) {
    for (int u = u0; u <= u1; ++u) {
      const Eigen::Vector2d p((u + 0.5) * s, (v + 0.5) * s);
      if ((p - c).norm() > r) continue;
      const std::int32_t id = ids.at(u, v);
      const auto it = std::find_if(out.begin(), out.end(), [&](const auto& e) { return e.first == id; });
      if (it == out.end()) out.emplace_back(id, 1);
      else ++it->second;
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

MarkStyle mark_style(int width, int height) {
  const double s = std::min(width, height) / 480.0;
  MarkStyle st;
  st.radius = std::max(9, static_cast<int>(std::lround(12 * s)));
  st.dot_radius = std::max(3, st.radius / 3);
  st.font = 0.48 * s;
  st.thickness = std::max(1, static_cast<int>(std::lround(1.6 * s)));
  return st;
}

MarkLayout layout_item_marks(const IdImage& ids, int scale, const Camera& camera, const std::vector<ItemMark>& items) {
  MarkLayout out;
  out.style = mark_style(camera.width, camera.height);
  const double r = out.style.radius, dot = out.style.dot_radius;
  const std::map<std::int32_t, Pixels> px = pixels_of(ids, items);
  // Every anchor first: a disc may cover none, placed or not.
  std::vector<PlacedMark> marks;
  std::vector<ItemMark> unplaced_items;
  for (const ItemMark& m : items) {
    const auto id = static_cast<std::int32_t>(m.object.index());
    const Pixels& p = px.at(id);
    PlacedMark pm;
    pm.number = m.number;
    pm.object = m.object;
    if (p.count > 0) {
      pm.anchor = deepest_pixel(ids, scale, id, p);
      pm.visible = true;
    } else {
      const auto at = camera.project(m.anchor_W);
      if (!at || at->x() < 0 || at->y() < 0 || at->x() >= camera.width || at->y() >= camera.height) continue;
      pm.anchor = *at;
    }
    marks.push_back(pm);
  }
  auto inside = [&](const Eigen::Vector2d& c) {
    return c.x() >= r + 1 && c.y() >= r + 1 && c.x() <= camera.width - r - 2 && c.y() <= camera.height - r - 2;
  };
  for (const PlacedMark& m : marks) {
    const auto own = static_cast<std::int32_t>(m.object.index());
    auto fits = [&](const Eigen::Vector2d& c) {
      if (!inside(c)) return false;
      for (const PlacedMark& other : marks) {
        if (other.number != m.number && (c - other.anchor).norm() < r + dot + 1) return false;
      }
      for (const PlacedMark& q : out.placed) {
        if ((c - q.disc).norm() < 2 * r + 2) return false;
        // This line through a placed disc, or a placed line through this disc.
        if (distance_to_segment(q.disc, m.anchor, c) < r + 1 || distance_to_segment(c, q.anchor, q.disc) < r + 1) {
          return false;
        }
        if (segments_cross(m.anchor, c, q.anchor, q.disc)) return false;
      }
      for (const PlacedMark& other : marks) {  // this line over another dot
        if (other.number != m.number && distance_to_segment(other.anchor, m.anchor, c) < dot + 2) return false;
      }
      for (const auto& [id, n] : under_disc(ids, scale, c, r + 1)) {
        if (id == own || id == IdImage::kNone) continue;
        const auto it = px.find(id);
        if (it != px.end() && n > kMaxCover * it->second.count) return false;
      }
      return true;
    };
    std::optional<Eigen::Vector2d> chosen;
    if (m.visible) {  // on the object itself, when it holds most of the disc
      const auto under = under_disc(ids, scale, m.anchor, r);
      int total = 0, mine = 0;
      for (const auto& [id, n] : under) {
        total += n;
        if (id == own) mine = n;
      }
      if (total > 0 && mine >= kOwnShare * total && fits(m.anchor)) chosen = m.anchor;
    }
    if (!chosen) {
      for (const Eigen::Vector2d& c : disc_candidates(m.anchor, r)) {
        if (fits(c)) {
          chosen = c;
          break;
        }
      }
    }
    if (!chosen) {
      const auto it = std::find_if(items.begin(), items.end(), [&](const ItemMark& i) { return i.number == m.number; });
      out.crowded.push_back(*it);
      continue;
    }
    PlacedMark placed = m;
    placed.disc = *chosen;
    out.placed.push_back(placed);
    const double pixels = static_cast<double>(px.at(own).count) * scale * scale;
    if (m.visible && pixels < kSmallShare * camera.width * camera.height) {
      out.small.push_back(*std::find_if(items.begin(), items.end(), [&](const ItemMark& i) { return i.number == m.number; }));
    }
  }
  return out;
}

std::vector<std::string> check_layout(const MarkLayout& layout, const IdImage& ids, int scale, int width, int height) {
  std::vector<std::string> problems;
  const double r = layout.style.radius, dot = layout.style.dot_radius;
  std::map<std::int32_t, int> visible;
  for (const PlacedMark& m : layout.placed) visible[static_cast<std::int32_t>(m.object.index())] = 0;
  for (const std::int32_t id : ids.ids) {
    if (const auto it = visible.find(id); it != visible.end()) ++it->second;
  }
  auto name = [](const PlacedMark& m) { return "mark " + std::to_string(m.number); };
  for (std::size_t i = 0; i < layout.placed.size(); ++i) {
    const PlacedMark& m = layout.placed[i];
    const auto own = static_cast<std::int32_t>(m.object.index());
    if (m.visible) {
      const int u = static_cast<int>(std::floor(m.anchor.x() / scale)), v = static_cast<int>(std::floor(m.anchor.y() / scale));
      if (u < 0 || v < 0 || u >= ids.width || v >= ids.height || ids.at(u, v) != own) {
        problems.push_back(name(m) + ": its dot is not on its object's visible pixels");
      }
    }
    if (m.disc.x() < r || m.disc.y() < r || m.disc.x() > width - r || m.disc.y() > height - r) {
      problems.push_back(name(m) + ": its disc leaves the image");
    }
    for (const auto& [id, n] : under_disc(ids, scale, m.disc, r)) {
      if (id == own || !visible.count(id)) continue;
      if (n > kMaxCover * visible.at(id)) {
        problems.push_back(name(m) + ": its disc covers " + std::to_string(100 * n / std::max(1, visible.at(id))) +
                           " % of another numbered object's visible pixels");
      }
    }
    for (std::size_t k = 0; k < layout.placed.size(); ++k) {
      if (k == i) continue;
      const PlacedMark& q = layout.placed[k];
      if ((m.disc - q.anchor).norm() < r + dot) problems.push_back(name(m) + ": its disc covers the dot of " + name(q));
      if (k > i && (m.disc - q.disc).norm() < 2 * r) problems.push_back(name(m) + " and " + name(q) + ": discs overlap");
      if (k > i && segments_cross(m.anchor, m.disc, q.anchor, q.disc)) {
        problems.push_back(name(m) + " and " + name(q) + ": leader lines cross");
      }
      if (!m.on_object() && distance_to_segment(q.anchor, m.anchor, m.disc) < dot) {
        problems.push_back(name(m) + ": its leader line runs over the dot of " + name(q));
      }
    }
  }
  return problems;
}

std::string zoom_name(std::size_t k) { return "Z" + std::to_string(k + 1); }

IdImage mark_pass(const graph::SceneGraph& g, const SceneGeometry& geometry, const episode::WorldState& s,
                  const Camera& camera, const std::vector<ItemMark>& items,
                  const std::vector<graph::ObjectId>& hidden) {
  const Camera pass = at_resolution(camera, std::max(1, camera.width / kMarkPassScale),
                                    std::max(1, camera.height / kMarkPassScale));
  std::vector<graph::ObjectId> targets;
  for (const ItemMark& m : items) targets.push_back(m.object);
  return draw_id_view_of(g, geometry, s, pass, targets, hidden).image;
}

namespace {

void add_zooms(const graph::SceneGraph& g, const SceneGeometry& geometry, const episode::WorldState& s,
               const std::vector<graph::ObjectId>& hidden, const Camera& camera, const MarkLayout& layout,
               const std::vector<ItemMark>& items, int depth,
               std::vector<Eigen::AlignedBox2d>& regions, std::vector<std::size_t>& region_zooms,
               std::vector<MarkedZoom>& zooms) {
  // Small marks are zoomed once; a zoom's own zooms are for what is crowded in it.
  for (ZoomView& z : zoom_views(camera, layout, items, /*with_small=*/depth > 1, /*max_views=*/4)) {
    regions.push_back(z.region);
    const std::size_t slot = zooms.size();
    region_zooms.push_back(slot);
    zooms.emplace_back();
    IdImage pass = mark_pass(g, geometry, s, z.camera, z.items, hidden);
    MarkLayout here = layout_item_marks(pass, kMarkPassScale, z.camera, z.items);
    std::vector<Eigen::AlignedBox2d> inner;
    std::vector<std::size_t> inner_zooms;
    if (depth > 1) add_zooms(g, geometry, s, hidden, z.camera, here, z.items, depth - 1, inner, inner_zooms, zooms);
    zooms[slot].view = std::move(z);
    zooms[slot].layout = std::move(here);
    zooms[slot].regions = std::move(inner);
    zooms[slot].region_zooms = std::move(inner_zooms);
    zooms[slot].pass = std::move(pass);
  }
}

}  // namespace

ItemMarksPlan plan_item_marks(const graph::SceneGraph& g, const SceneGeometry& geometry, const episode::WorldState& s,
                              const Camera& camera, const std::vector<ItemMark>& items,
                              const std::vector<graph::ObjectId>& hidden) {
  return plan_item_marks(g, geometry, s, camera, items, hidden, mark_pass(g, geometry, s, camera, items, hidden));
}

ItemMarksPlan plan_item_marks(const graph::SceneGraph& g, const SceneGeometry& geometry, const episode::WorldState& s,
                              const Camera& camera, const std::vector<ItemMark>& items,
                              const std::vector<graph::ObjectId>& hidden, const IdImage& pass) {
  ItemMarksPlan plan;
  plan.camera = camera;
  plan.items = items;
  plan.layout = layout_item_marks(pass, kMarkPassScale, camera, items);
  plan.pass = pass;
  add_zooms(g, geometry, s, hidden, camera, plan.layout, items, /*depth=*/2, plan.regions, plan.region_zooms,
            plan.zooms);
  return plan;
}

bool ItemMarksPlan::placed(int number) const {
  auto in = [&](const MarkLayout& l) {
    return std::any_of(l.placed.begin(), l.placed.end(), [&](const PlacedMark& m) { return m.number == number; });
  };
  return in(layout) || std::any_of(zooms.begin(), zooms.end(), [&](const MarkedZoom& z) { return in(z.layout); });
}

std::vector<std::string> ItemMarksPlan::problems() const {
  std::vector<std::string> out;
  auto check = [&](const std::string& picture, const MarkLayout& l, const IdImage& ids, const Camera& cam) {
    for (const std::string& p : check_layout(l, ids, kMarkPassScale, cam.width, cam.height)) out.push_back(picture + ": " + p);
  };
  check("picture", layout, pass, camera);
  for (std::size_t k = 0; k < zooms.size(); ++k) check(zoom_name(k), zooms[k].layout, zooms[k].pass, zooms[k].view.camera);
  return out;
}

std::vector<ZoomFrame> zoom_frames(const Camera& camera, std::vector<ZoomPoint> points, double radius, int max_views) {
  std::vector<ZoomFrame> out;
  if (points.empty() || camera.orthographic || max_views < 1) return out;
  std::sort(points.begin(), points.end(), [](const ZoomPoint& a, const ZoomPoint& b) {
    return a.at.x() != b.at.x() ? a.at.x() < b.at.x() : a.number < b.number;
  });
  // Clusters along the image's width: a gap of a quarter of the image starts a new one, and so
  // does a cluster that would grow wider than a third of it (a zoom shows at least twice as big).
  std::vector<std::vector<ZoomPoint>> clusters;
  for (const ZoomPoint& p : points) {
    if (clusters.empty() || p.at.x() - clusters.back().back().at.x() > camera.width / 4.0 ||
        p.at.x() - clusters.back().front().at.x() > camera.width / 3.0) {
      clusters.emplace_back();
    }
    clusters.back().push_back(p);
  }
  // Fewer views than clusters: neighbouring clusters share one.
  while (static_cast<int>(clusters.size()) > max_views) {
    std::size_t best = 0;
    double gap = 1e18;
    for (std::size_t k = 0; k + 1 < clusters.size(); ++k) {
      const double g = clusters[k + 1].front().at.x() - clusters[k].back().at.x();
      if (g < gap) {
        gap = g;
        best = k;
      }
    }
    clusters[best].insert(clusters[best].end(), clusters[best + 1].begin(), clusters[best + 1].end());
    clusters.erase(clusters.begin() + static_cast<std::ptrdiff_t>(best) + 1);
  }
  const double aspect = camera.aspect();
  for (const auto& cluster : clusters) {
    Eigen::AlignedBox2d box;
    for (const ZoomPoint& p : cluster) box.extend(p.at);
    // A margin for the things around the points, and at least a third of the picture; at most
    // half of it, so the zoom shows things at least twice as big (what does not fit is cut).
    Eigen::Vector2d half = box.sizes() / 2.0 + Eigen::Vector2d::Constant(5.0 * radius);
    half = half.cwiseMax(Eigen::Vector2d(camera.width / 6.0, camera.height / 6.0));
    if (half.x() < half.y() * aspect) half.x() = half.y() * aspect;
    else half.y() = half.x() / aspect;
    half = half.cwiseMin(Eigen::Vector2d(camera.width / 4.0, camera.height / 4.0));
    Eigen::Vector2d centre = box.center();
    centre = centre.cwiseMax(half).cwiseMin(Eigen::Vector2d(camera.width, camera.height) - half);
    ZoomFrame z;
    z.region = Eigen::AlignedBox2d(centre - half, centre + half);
    for (const ZoomPoint& p : cluster) z.numbers.push_back(p.number);
    // The same eye, looking through the region's centre, with the lens narrowed to it.
    const double t = std::tan(camera.fovy / 2.0);
    const Eigen::Vector3d dir_C((2.0 * centre.x() / camera.width - 1.0) * t * aspect,
                                (1.0 - 2.0 * centre.y() / camera.height) * t, -1.0);
    const Eigen::Vector3d eye = camera.X_WC.translation();
    z.camera = camera;
    z.camera.X_WC = look_at(eye, eye + camera.X_WC.linear() * dir_C);
    z.camera.fovy = 2.0 * std::atan(t * (2.0 * half.y()) / camera.height);
    out.push_back(std::move(z));
  }
  return out;
}

std::vector<ZoomView> zoom_views(const Camera& camera, const MarkLayout& layout, const std::vector<ItemMark>& items,
                                 bool with_small, int max_views) {
  std::vector<ItemMark> wanted = layout.crowded;
  if (with_small) wanted.insert(wanted.end(), layout.small.begin(), layout.small.end());
  // The wanted marks' anchors, where they would be (their projected top centre).
  std::vector<ZoomPoint> points;
  for (const ItemMark& m : wanted) {
    const auto placed = std::find_if(layout.placed.begin(), layout.placed.end(),
                                     [&](const PlacedMark& p) { return p.number == m.number; });
    const auto at = placed != layout.placed.end() ? std::optional<Eigen::Vector2d>(placed->anchor)
                                                  : camera.project(m.anchor_W);
    if (at) points.push_back({m.number, *at});
  }
  std::vector<ZoomView> out;
  for (ZoomFrame& f : zoom_frames(camera, std::move(points), layout.style.radius, max_views)) {
    ZoomView z;
    z.region = f.region;
    z.camera = f.camera;
    for (const ItemMark& m : items) {
      const auto placed = std::find_if(layout.placed.begin(), layout.placed.end(),
                                       [&](const PlacedMark& p) { return p.number == m.number; });
      const bool crowded_here = std::find(f.numbers.begin(), f.numbers.end(), m.number) != f.numbers.end();
      if (crowded_here || (placed != layout.placed.end() && z.region.contains(placed->anchor))) z.items.push_back(m);
    }
    out.push_back(std::move(z));
  }
  return out;
}

}  // namespace mtg::render
