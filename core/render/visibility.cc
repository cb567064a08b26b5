#include "core/render/visibility.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "core/render/mark_layout.h"
#include "core/render/view.h"
#include "core/util/error.h"
#include "core/util/parallel.h"

namespace mtg::render {

// Where a world box lands in normalised device coordinates (x, y across the image, z depth);
// `anywhere` when it reaches behind the camera, so its image could cover every pixel.
struct NdcBox {
  Eigen::AlignedBox3f box;
  bool anywhere = false;
};

namespace {

Eigen::AlignedBox3d world_box(const geom::Ring& footprint, double bottom, double top) {
  Eigen::AlignedBox3d box;
  for (const auto& q : footprint) {
    box.extend(Eigen::Vector3d(q.x(), q.y(), bottom));
    box.extend(Eigen::Vector3d(q.x(), q.y(), top));
  }
  return box;
}

NdcBox ndc_box(const Eigen::Matrix4f& clip_from_world, const Eigen::AlignedBox3d& box_W) {
  NdcBox out;
  unsigned all_out = 0x3f;  // the frustum sides every corner lies outside of (may_show)
  for (int k = 0; k < 8; ++k) {
    const Eigen::Vector3d corner = box_W.corner(static_cast<Eigen::AlignedBox3d::CornerType>(k));
    const Eigen::Vector4f c = clip_from_world * Eigen::Vector4f(static_cast<float>(corner.x()),
                                                                static_cast<float>(corner.y()),
                                                                static_cast<float>(corner.z()), 1.0f);
    all_out &= (c.x() < -c.w() ? 1u : 0u) | (c.x() > c.w() ? 2u : 0u) | (c.y() < -c.w() ? 4u : 0u) |
               (c.y() > c.w() ? 8u : 0u) | (c.z() < -c.w() ? 16u : 0u) | (c.z() > c.w() ? 32u : 0u);
    if (c.w() <= 1e-6f) {
      out.anywhere = true;
      continue;
    }
    out.box.extend(Eigen::Vector3f(c.x() / c.w(), c.y() / c.w(), c.z() / c.w()));
  }
  if (all_out != 0 || box_W.isEmpty()) return {};  // nowhere in the picture
  if (out.anywhere) {
    const float farthest = out.box.isEmpty() ? 1.0f : out.box.max().z();
    out.box.extend(Eigen::Vector3f(-1.0f, -1.0f, -1.0f));
    out.box.extend(Eigen::Vector3f(1.0f, 1.0f, farthest));
  }
  return out;
}

// Whether something inside `in_front` can cover part of `target` in the image: their images
// overlap and some of it is nearer than the farthest of the target.
bool may_cover(const NdcBox& in_front, const NdcBox& target) {
  if (in_front.box.isEmpty() || target.box.isEmpty()) return false;
  return in_front.box.min().x() <= target.box.max().x() && in_front.box.max().x() >= target.box.min().x() &&
         in_front.box.min().y() <= target.box.max().y() && in_front.box.max().y() >= target.box.min().y() &&
         in_front.box.min().z() <= target.box.max().z();
}

// The entry of `o` in a list sorted by object index, or zero pixels.
ObjectSight sight_of(const std::vector<ObjectSight>& sorted, graph::ObjectId o) {
  const auto index = static_cast<std::int32_t>(o.index());
  const auto it = std::lower_bound(sorted.begin(), sorted.end(), index,
                                   [](const ObjectSight& a, std::int32_t i) { return a.object < i; });
  if (it == sorted.end() || it->object != index) return {index, 0, 0};
  return *it;
}

void add_silhouette(std::vector<ObjectSight>& out, graph::ObjectId o, int pixels) {
  if (pixels > 0) out.push_back({static_cast<std::int32_t>(o.index()), 0, pixels});
}

}  // namespace

nlohmann::json VisibilityOptions::to_json() const {
  return {{"image", {image_width, image_height}}, {"pass_scale", pass_scale}, {"min_share", min_share},
          {"min_pixels", min_pixels}, {"min_gap", min_gap}};
}

ViewSight::ViewSight(Camera image_camera, std::vector<ObjectSight> objects, const VisibilityOptions& options)
    : camera_(std::move(image_camera)), objects_(std::move(objects)), options_(options) {
  pixel_area_ = static_cast<double>(options.image_width) * options.image_height /
                (static_cast<double>(options.pass_width()) * options.pass_height());
}

ObjectSight ViewSight::of(graph::ObjectId o) const { return sight_of(objects_, o); }

double ViewSight::image_pixels(graph::ObjectId o) const { return of(o).visible * pixel_area_; }



bool ViewSight::clearly_visible(graph::ObjectId o) const {
  const ObjectSight seen = of(o);
  return seen.visible * pixel_area_ >= options_.min_pixels && seen.share() >= options_.min_share;
}

std::vector<ObjectSight> count_pixels(const IdImage& image, std::vector<ObjectSight> silhouettes) {
  std::int32_t max_id = -1;
  for (const ObjectSight& o : silhouettes) max_id = std::max(max_id, o.object);
  std::vector<int> counts(static_cast<std::size_t>(max_id + 1), 0);
  for (const std::int32_t id : image.ids) {
    if (id >= 0 && id <= max_id) ++counts[static_cast<std::size_t>(id)];
  }
  for (ObjectSight& o : silhouettes) o.visible = counts[static_cast<std::size_t>(o.object)];
  return silhouettes;
}

IdView draw_id_view(const graph::SceneGraph& g, const SceneGeometry& geometry, const episode::WorldState& s,
                    const Camera& camera, const std::vector<graph::ObjectId>& hidden, graph::ObjectId only) {
  IdPass pass(camera);
  std::vector<ObjectSight> silhouettes;
  for (const graph::ObjectId o : g.objects.ids()) {
    if (only.valid() ? o != only : (o == s.held || std::find(hidden.begin(), hidden.end(), o) != hidden.end())) {
      continue;
    }
    if (o.index() >= geometry.size() || geometry.of(o).indices.empty()) continue;
    // Out of the picture altogether (its box is; what it draws lies inside its box).
    const episode::ObjectState& st = s.objects[o];
    if (!st.footprint.empty() && !may_show(pass.clip_from_world(), world_box(st.footprint, st.bottom, st.top))) continue;
    add_silhouette(silhouettes, o, pass.draw(geometry.of(o), object_pose(g, s, o), static_cast<std::int32_t>(o.index())));
  }
  IdView out;
  out.image = pass.take();
  out.objects = count_pixels(out.image, std::move(silhouettes));
  return out;
}

IdView draw_id_view_of(const graph::SceneGraph& g, const SceneGeometry& geometry, const episode::WorldState& s,
                       const Camera& camera, const std::vector<graph::ObjectId>& targets,
                       const std::vector<graph::ObjectId>& hidden) {
  IdPass pass(camera);
  auto box_of = [&](graph::ObjectId o) {
    const episode::ObjectState& st = s.objects[o];
    return ndc_box(pass.clip_from_world(), world_box(st.footprint, st.bottom, st.top));
  };
  std::vector<NdcBox> target_boxes;
  for (const graph::ObjectId t : targets) target_boxes.push_back(box_of(t));
  std::vector<ObjectSight> silhouettes;
  for (const graph::ObjectId o : g.objects.ids()) {
    if (o == s.held || std::find(hidden.begin(), hidden.end(), o) != hidden.end()) continue;
    if (o.index() >= geometry.size() || geometry.of(o).indices.empty() || s.objects[o].footprint.empty()) continue;
    const bool target = std::find(targets.begin(), targets.end(), o) != targets.end();
    if (!target) {
      const NdcBox b = box_of(o);
      if (!std::any_of(target_boxes.begin(), target_boxes.end(), [&](const NdcBox& t) { return may_cover(b, t); })) {
        continue;
      }
    }
    add_silhouette(silhouettes, o, pass.draw(geometry.of(o), object_pose(g, s, o), static_cast<std::int32_t>(o.index())));
  }
  IdView out;
  out.image = pass.take();
  out.objects = count_pixels(out.image, std::move(silhouettes));
  return out;
}

struct VisibilityOracle::Scenery {
  Camera image_camera;
  Camera pass_camera;
  Eigen::Matrix4f clip_from_world;
  IdImage background;                    // everything that never moves, in the platform's window
  std::vector<ObjectSight> silhouettes;  // of the scenery there, by object index
  std::vector<NdcBox> initial_boxes;     // each object's image where the graph found it
};

// What decides a view of a platform's objects in one state.
struct VisibilityOracle::Deciders {
  std::string key;                       // the view's memo key
  std::vector<graph::ObjectId> on;       // the platform's objects (not the held one)
  std::vector<graph::ObjectId> items;    // the items to draw: its own, and those that may cover them
  int left = 0, top = 0, width = 0, height = 0;  // the pass pixels the platform's objects may cover
};

VisibilityOracle::VisibilityOracle(const graph::SceneGraph& g, const SceneGeometry& geometry, VisibilityOptions options)
    : g_(g), geometry_(geometry), options_(options), scenery_(g.platforms.size() * 4) {
  MTG_DEMAND(geometry.size() == g.objects.size(), "visibility: the geometry is of another graph");
  for (const graph::ObjectId o : g.objects.ids()) {
    if (g.objects[o].pickable()) movable_.push_back(o);
    boxes_.push_back(world_box(g.objects[o].footprint, g.objects[o].bottom, g.objects[o].top));
  }
}

VisibilityOracle::~VisibilityOracle() = default;

Eigen::AlignedBox3d VisibilityOracle::box_in(const episode::WorldState& s, graph::ObjectId o) const {
  // Objects move without turning (episode::place_held), so their box moves along.
  const Eigen::Vector3d shift = s.objects[o].position - g_.objects[o].X_WO.translation();
  Eigen::AlignedBox3d box = boxes_[o.index()];
  box.translate(shift);
  return box;
}

// The pass pixels an NDC box may cover, a pixel wider all round, inside the image.
static void pixel_window(const Eigen::AlignedBox3f& box, int W, int H, int& left, int& top, int& width,
                         int& height) {
  const float x0 = (box.min().x() + 1.0f) * 0.5f * static_cast<float>(W);
  const float x1 = (box.max().x() + 1.0f) * 0.5f * static_cast<float>(W);
  const float y0 = (1.0f - box.max().y()) * 0.5f * static_cast<float>(H);
  const float y1 = (1.0f - box.min().y()) * 0.5f * static_cast<float>(H);
  auto clamp = [](float v, int hi) { return std::clamp(static_cast<int>(std::floor(v)), 0, hi); };
  left = clamp(x0 - 1.0f, W);
  top = clamp(y0 - 1.0f, H);
  width = clamp(x1 + 2.0f, W) - left;
  height = clamp(y1 + 2.0f, H) - top;
}

const VisibilityOracle::Scenery& VisibilityOracle::scenery(graph::PlatformId platform, int side) const {
  const std::size_t slot = platform.index() * 4 + static_cast<std::size_t>(side);
  SceneryOnce& once = scenery_.at(slot);
  std::call_once(once.flag, [&] { once.scenery = make_scenery(platform, side); });
  return *once.scenery;
}

void VisibilityOracle::prepare(int jobs) const {
  parallel_for(g_.navigable.size(), jobs, [&](std::size_t k) {
    const graph::PlatformId p = g_.navigable[k];
    scenery(p, std::max(0, g_.platforms[p].default_side));
  });
}

std::unique_ptr<VisibilityOracle::Scenery> VisibilityOracle::make_scenery(graph::PlatformId platform, int side) const {
  auto sc = std::make_unique<Scenery>();
  const episode::WorldState initial = episode::initial_state(g_);
  sc->image_camera = platform_camera(g_, initial, platform, side, options_.image_width, options_.image_height);
  sc->pass_camera = at_resolution(sc->image_camera, options_.pass_width(), options_.pass_height());
  sc->clip_from_world = sc->pass_camera.clip_from_world();
  // The window where anything on the platform can show: its surface up to the layer above (at
  // most 1.5 m), and what stands on it now.
  const graph::Platform& p = g_.platforms[platform];
  const double h = p.height;
  const double up = std::isfinite(p.clearance) ? std::min(p.clearance, 1.5) : 1.5;
  NdcBox reach;
  Eigen::AlignedBox3d surface;
  for (const geom::Ring& ring : p.polygon_W().rings) {
    for (const auto& q : ring) {
      surface.extend(Eigen::Vector3d(q.x(), q.y(), h));
      surface.extend(Eigen::Vector3d(q.x(), q.y(), h + up));
    }
  }
  surface.min() -= Eigen::Vector3d(0.05, 0.05, 0.0);
  surface.max() += Eigen::Vector3d(0.05, 0.05, 0.0);
  reach.box.extend(ndc_box(sc->clip_from_world, surface).box);
  for (const graph::ObjectId o : episode::everything_on(g_, initial, platform)) {
    reach.box.extend(ndc_box(sc->clip_from_world, boxes_[o.index()]).box);
  }
  int left = 0, top = 0, width = 0, height = 0;
  if (!reach.box.isEmpty()) {
    pixel_window(reach.box, sc->pass_camera.width, sc->pass_camera.height, left, top, width, height);
  }
  // Scenery that can cover none of the window (beside it in the picture, or behind all of it)
  // is left out: it changes none of the pixels the platform's objects can take.
  IdPass pass(sc->pass_camera, IdImage(left, top, width, height));
  for (const graph::ObjectId o : g_.objects.ids()) {
    if (g_.objects[o].pickable() || geometry_.of(o).indices.empty()) continue;
    if (!may_cover(ndc_box(sc->clip_from_world, boxes_[o.index()]), reach)) continue;
    add_silhouette(sc->silhouettes, o,
                   pass.draw(geometry_.of(o), object_pose(g_, initial, o), static_cast<std::int32_t>(o.index())));
  }
  sc->background = pass.take();
  for (const graph::ObjectId o : g_.objects.ids()) sc->initial_boxes.push_back(ndc_box(sc->clip_from_world, boxes_[o.index()]));
  return sc;
}

NdcBox VisibilityOracle::image_box(const episode::WorldState& s, graph::ObjectId o, const Scenery& sc) const {
  // Most objects stand where the graph found them: their image is known.
  if (s.objects[o].position == g_.objects[o].X_WO.translation()) return sc.initial_boxes[o.index()];
  return ndc_box(sc.clip_from_world, box_in(s, o));
}

VisibilityOracle::Deciders VisibilityOracle::deciders(const episode::WorldState& s, graph::PlatformId platform,
                                                      int side, const Scenery& sc) const {
  // The platform's objects, and the items that may stand in front of them: nothing else changes
  // their pixels (the scenery is drawn already, and an item behind them or beside them in the
  // picture covers none of theirs).
  Deciders d;
  append_key(d.key, static_cast<std::int64_t>(platform.index() * 4 + static_cast<std::size_t>(side)));
  for (const graph::ObjectId o : episode::everything_on(g_, s, platform)) {
    if (o != s.held) d.on.push_back(o);
  }
  std::sort(d.on.begin(), d.on.end());
  std::vector<NdcBox> targets;
  Eigen::AlignedBox3f all;
  for (const graph::ObjectId o : d.on) {
    targets.push_back(image_box(s, o, sc));
    all.extend(targets.back().box);
  }
  if (all.isEmpty()) return d;  // nothing on it to see
  for (const graph::ObjectId o : movable_) {
    if (o == s.held) continue;
    const bool own = std::binary_search(d.on.begin(), d.on.end(), o);
    if (!own) {
      const NdcBox b = image_box(s, o, sc);
      // Most items are nowhere near the platform's objects in the picture: one test for all.
      if (!may_cover(b, NdcBox{all, false})) continue;
      if (!std::any_of(targets.begin(), targets.end(), [&](const NdcBox& t) { return may_cover(b, t); })) continue;
    }
    d.items.push_back(o);
    const Eigen::Vector3d& at = s.objects[o].position;
    append_key(d.key, static_cast<std::int64_t>(o.index()));
    append_key(d.key, at.x());
    append_key(d.key, at.y());
    append_key(d.key, at.z());
  }
  pixel_window(all, sc.pass_camera.width, sc.pass_camera.height, d.left, d.top, d.width, d.height);
  return d;
}

std::vector<std::int32_t> VisibilityOracle::readable_marks(const episode::WorldState& s,
                                                          const std::vector<ItemMark>& items,
                                                          const Camera& image_camera, const IdImage& pass) const {
  const ItemMarksPlan plan = plan_item_marks(g_, geometry_, s, image_camera, items, {}, pass);
  std::vector<std::int32_t> out;
  for (const ItemMark& m : items) {
    if (plan.placed(m.number)) out.push_back(static_cast<std::int32_t>(m.object.index()));
  }
  std::sort(out.begin(), out.end());
  return out;
}

bool VisibilityOracle::in_view(const episode::WorldState& s, graph::PlatformId platform, graph::ObjectId o) const {
  const int side = std::max(0, g_.platforms.at(platform).default_side);
  const Deciders d = deciders(s, platform, side, scenery(platform, side));
  return std::find(d.items.begin(), d.items.end(), o) != d.items.end();
}

std::string VisibilityOracle::view_key(const episode::WorldState& s, graph::PlatformId platform) const {
  const int side = std::max(0, g_.platforms.at(platform).default_side);
  std::string key = deciders(s, platform, side, scenery(platform, side)).key;
  append_key(key, s.platform_offset.at(platform).x());
  append_key(key, s.platform_offset.at(platform).y());
  append_key(key, s.platform_offset.at(platform).z());
  return key;
}

std::shared_ptr<const ViewSight> VisibilityOracle::arrival_view(const episode::WorldState& s,
                                                                graph::PlatformId platform) const {
  return view(s, platform, std::max(0, g_.platforms.at(platform).default_side));
}

IdImage VisibilityOracle::draw_window(const episode::WorldState& s, const Scenery& sc, const Deciders& d,
                                      std::vector<ObjectSight>& silhouettes) const {
  const IdImage& bg = sc.background;
  const bool inside = d.left >= bg.left && d.top >= bg.top && d.left + d.width <= bg.left + bg.width &&
                      d.top + d.height <= bg.top + bg.height;
  std::optional<IdPass> pass;
  if (inside) {
    pass.emplace(sc.pass_camera, bg.window(d.left, d.top, d.width, d.height));
    for (const graph::ObjectId o : d.on) {
      if (g_.objects[o].pickable()) continue;
      const ObjectSight kept = sight_of(sc.silhouettes, o);
      if (kept.silhouette > 0) silhouettes.push_back(kept);
    }
  } else {
    // Something on the platform reaches out of the window drawn beforehand (an item placed
    // overhanging it): the scenery of this window is drawn afresh, the same pixels.
    pass.emplace(sc.pass_camera, IdImage(d.left, d.top, d.width, d.height));
    for (const graph::ObjectId o : g_.objects.ids()) {
      if (g_.objects[o].pickable() || geometry_.of(o).indices.empty()) continue;
      const int pixels = pass->draw(geometry_.of(o), object_pose(g_, s, o), static_cast<std::int32_t>(o.index()));
      if (std::binary_search(d.on.begin(), d.on.end(), o)) add_silhouette(silhouettes, o, pixels);
    }
  }
  for (const graph::ObjectId o : d.items) {
    const int pixels = pass->draw(geometry_.of(o), object_pose(g_, s, o), static_cast<std::int32_t>(o.index()));
    if (std::binary_search(d.on.begin(), d.on.end(), o)) add_silhouette(silhouettes, o, pixels);
  }
  std::sort(silhouettes.begin(), silhouettes.end(),
            [](const ObjectSight& a, const ObjectSight& b) { return a.object < b.object; });
  return pass->take();
}

std::shared_ptr<const ViewSight> VisibilityOracle::view(const episode::WorldState& s, graph::PlatformId platform,
                                                        int side) const {
  MTG_DEMAND(side >= 0 && side <= 3, "visibility: side out of range");
  if (!s.platform_offset.at(platform).isZero()) {
    // A platform that moved with its item: no scenery drawing fits it; draw it all.
    const Camera image_camera =
        platform_camera(g_, s, platform, side, options_.image_width, options_.image_height);
    IdView v = draw_id_view(g_, geometry_, s, at_resolution(image_camera, options_.pass_width(), options_.pass_height()));
    return std::make_shared<const ViewSight>(image_camera, std::move(v.objects), options_);
  }
  const Scenery& sc = scenery(platform, side);
  const Deciders d = deciders(s, platform, side, sc);
  return drawn_.get(d.key, [&] {
    const std::shared_ptr<const Window> w = window(s, sc, d);
    return std::make_shared<const ViewSight>(sc.image_camera, count_pixels(w->image, w->silhouettes), options_);
  });
}

std::shared_ptr<const VisibilityOracle::Window> VisibilityOracle::window(const episode::WorldState& s,
                                                                         const Scenery& sc, const Deciders& d) const {
  return windows_.get(d.key, [&] {
    auto w = std::make_shared<Window>();
    w->image = draw_window(s, sc, d, w->silhouettes);
    return std::shared_ptr<const Window>(std::move(w));
  });
}

bool VisibilityOracle::mark_readable(const episode::WorldState& s, graph::PlatformId platform, graph::ObjectId o) const {
  const int side = std::max(0, g_.platforms.at(platform).default_side);
  const auto index = static_cast<std::int32_t>(o.index());
  const std::vector<ItemMark> items = item_marks(g_, s, platform);
  if (!s.platform_offset.at(platform).isZero()) {
    const Camera image_camera = platform_camera(g_, s, platform, side, options_.image_width, options_.image_height);
    const IdImage whole =
        draw_id_view(g_, geometry_, s, at_resolution(image_camera, options_.pass_width(), options_.pass_height())).image;
    const std::vector<std::int32_t> readable = readable_marks(s, items, image_camera, whole);
    return std::binary_search(readable.begin(), readable.end(), index);
  }
  const Scenery& sc = scenery(platform, side);
  const Deciders d = deciders(s, platform, side, sc);
  // The items' numbers (their order on the platform) decide where their marks go too.
  std::string key = d.key;
  for (const ItemMark& m : items) append_key(key, static_cast<std::int64_t>(m.object.index()));
  // The numbered objects are all inside the window, and their pixels there are those of a whole
  // pass: laid out on it, the marks go where the renderer puts them.
  auto whole = [&] {
    const std::shared_ptr<const Window> w = window(s, sc, d);
    IdImage out(sc.pass_camera.width, sc.pass_camera.height);
    for (int v = 0; v < w->image.height; ++v) {
      for (int u = 0; u < w->image.width; ++u) {
        out.ids[static_cast<std::size_t>(w->image.top + v) * static_cast<std::size_t>(out.width) +
                static_cast<std::size_t>(w->image.left + u)] = w->image.at(u, v);
      }
    }
    return out;
  };
  // The picture itself first: most marks have their place there, and the zooms (drawn anew)
  // are worked out only for a mark that has not.
  const std::shared_ptr<const MarksInPicture> main = in_picture_.get(key, [&] {
    const MarkLayout layout = layout_item_marks(whole(), kMarkPassScale, sc.image_camera, items);
    auto m = std::make_shared<MarksInPicture>();
    for (const PlacedMark& p : layout.placed) m->placed.push_back(static_cast<std::int32_t>(p.object.index()));
    for (const ItemMark& c : layout.crowded) m->crowded.push_back(static_cast<std::int32_t>(c.object.index()));
    std::sort(m->placed.begin(), m->placed.end());
    std::sort(m->crowded.begin(), m->crowded.end());
    return std::shared_ptr<const MarksInPicture>(std::move(m));
  });
  if (std::binary_search(main->placed.begin(), main->placed.end(), index)) return true;
  if (!std::binary_search(main->crowded.begin(), main->crowded.end(), index)) return false;
  const std::shared_ptr<const std::vector<std::int32_t>> readable = with_zooms_.get(key, [&] {
    return std::make_shared<const std::vector<std::int32_t>>(readable_marks(s, items, sc.image_camera, whole()));
  });
  return std::binary_search(readable->begin(), readable->end(), index);
}

}  // namespace mtg::render
