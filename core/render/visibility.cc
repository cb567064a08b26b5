#include "core/render/visibility.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
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

// An item where it stands, in a memo key.
void append_item(std::string& key, graph::ObjectId o, const Eigen::Vector3d& at) {
  append_key(key, static_cast<std::int64_t>(o.index()));
  append_key(key, at.x());
  append_key(key, at.y());
  append_key(key, at.z());
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

struct ViewSight::Slot {
  Camera camera;
  Count count;
  std::once_flag once;
  std::shared_ptr<const std::vector<ObjectSight>> objects;
};

ViewSight::ViewSight(Camera image_camera, std::vector<ObjectSight> objects, const VisibilityOptions& options)
    : ViewSight(std::vector<Picture>{{std::move(image_camera), std::move(objects)}}, options) {}

ViewSight::ViewSight(std::vector<Picture> pictures, const VisibilityOptions& options) : options_(options) {
  MTG_DEMAND(!pictures.empty(), "visibility: a view has at least one picture");
  for (Picture& p : pictures) {
    auto slot = std::make_unique<Slot>();
    slot->camera = std::move(p.camera);
    slot->objects = std::make_shared<const std::vector<ObjectSight>>(std::move(p.objects));
    std::call_once(slot->once, [] {});
    pictures_.push_back(std::move(slot));
  }
  pixel_area_ = static_cast<double>(options.image_width) * options.image_height /
                (static_cast<double>(options.pass_width()) * options.pass_height());
}

ViewSight::ViewSight(std::vector<Camera> cameras, std::vector<Count> counts, const VisibilityOptions& options)
    : options_(options) {
  MTG_DEMAND(!cameras.empty() && cameras.size() == counts.size(), "visibility: one count per picture");
  for (std::size_t k = 0; k < cameras.size(); ++k) {
    auto slot = std::make_unique<Slot>();
    slot->camera = std::move(cameras[k]);
    slot->count = std::move(counts[k]);
    pictures_.push_back(std::move(slot));
  }
  pixel_area_ = static_cast<double>(options.image_width) * options.image_height /
                (static_cast<double>(options.pass_width()) * options.pass_height());
}

ViewSight::~ViewSight() = default;

const Camera& ViewSight::camera(std::size_t k) const { return pictures_.at(k)->camera; }

const std::vector<ObjectSight>& ViewSight::objects(std::size_t k) const {
  Slot& slot = *pictures_.at(k);
  std::call_once(slot.once, [&] {
    slot.objects = slot.count();
    slot.count = nullptr;  // what it held (the deciders) is not needed again
  });
  return *slot.objects;
}

ObjectSight ViewSight::of(std::size_t k, graph::ObjectId o) const { return sight_of(objects(k), o); }

ObjectSight ViewSight::of(graph::ObjectId o) const {
  ObjectSight best = of(0, o);
  for (std::size_t k = 1; k < pictures_.size(); ++k) {
    const ObjectSight here = of(k, o);
    if (here.visible > best.visible) best = here;
  }
  return best;
}

double ViewSight::image_pixels(graph::ObjectId o) const { return of(o).visible * pixel_area_; }

double ViewSight::image_pixels_in(std::size_t k, graph::ObjectId o) const { return of(k, o).visible * pixel_area_; }

bool ViewSight::clearly_visible_in(std::size_t k, graph::ObjectId o) const {
  const ObjectSight seen = of(k, o);
  return seen.visible * pixel_area_ >= options_.min_pixels && seen.share() >= options_.min_share;
}

bool ViewSight::clearly_visible(graph::ObjectId o) const {
  for (std::size_t k = 0; k < pictures_.size(); ++k) {
    if (clearly_visible_in(k, o)) return true;
  }
  return false;
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
    if (only.valid() ? o != only
                     : (episode::carried(g, s, o) || std::find(hidden.begin(), hidden.end(), o) != hidden.end())) {
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
    if (episode::carried(g, s, o) || std::find(hidden.begin(), hidden.end(), o) != hidden.end()) continue;
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

namespace {

// A picture's scenery as it is kept between states: the pixels of an id pass's window, with the
// object ids in 16 bits where the graph's objects fit (every scene a person furnishes: 32,767
// objects), else in 32. A scene's scenery is a quarter of its generation's peak memory (28 MB of
// apt_0's); ids take half of it.
class SceneryPixels {
 public:
  SceneryPixels() = default;
  SceneryPixels(IdImage image, bool narrow)
      : left_(image.left), top_(image.top), width_(image.width), height_(image.height), depth_(std::move(image.depth)) {
    if (narrow) {
      narrow_.assign(image.ids.begin(), image.ids.end());
    } else {
      wide_ = std::move(image.ids);
    }
  }

  bool holds(int l, int t, int w, int h) const {
    return l >= left_ && t >= top_ && l + w <= left_ + width_ && t + h <= top_ + height_;
  }
  /// The window `l, t, w, h` (which holds() must accept) as an id image: IdImage::window's pixels.
  IdImage window(int l, int t, int w, int h) const {
    IdImage out = IdImage::unfilled(l, t, w, h);
    if (wide_.empty()) {
      append_window(narrow_, left_, top_, width_, l, t, w, h, out.ids);
    } else {
      append_window(wide_, left_, top_, width_, l, t, w, h, out.ids);
    }
    append_window(depth_, left_, top_, width_, l, t, w, h, out.depth);
    return out;
  }

 private:
  int left_ = 0, top_ = 0, width_ = 0, height_ = 0;
  std::vector<std::int16_t> narrow_;
  std::vector<std::int32_t> wide_;
  std::vector<float> depth_;
};

}  // namespace

// One picture of a view: its camera and its drawing of everything that never moves.
struct VisibilityOracle::PictureScenery {
  PlatformPicture picture;
  std::int64_t slot = 0;                 // the picture's place in memo keys
  Camera pass_camera;
  Eigen::Matrix4f clip_from_world;
  SceneryPixels background;              // everything that never moves, in the platform's window
  std::vector<ObjectSight> silhouettes;  // of the scenery there, by object index
  std::vector<NdcBox> initial_boxes;     // each object's image where the graph found it
};

// The pictures of the view of one platform from one side.
struct VisibilityOracle::Scenery {
  std::vector<PictureScenery> pictures;
};

// What decides a picture of a platform's objects in one state.
struct VisibilityOracle::Deciders {
  std::string key;                       // the picture's memo key
  std::vector<graph::ObjectId> on;       // the platform's objects (not the held one)
  std::vector<graph::ObjectId> items;    // the items to draw: its own, and those that may cover them
  std::vector<Eigen::Vector3d> at;       // where each of `items` stands
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
  auto out = std::make_unique<Scenery>();
  const episode::WorldState initial = episode::initial_state(g_);
  const std::vector<PlatformPicture> pictures =
      platform_pictures(g_, initial, platform, side, options_.image_width, options_.image_height);
  for (std::size_t k = 0; k < pictures.size(); ++k) {
    PictureScenery& sc = out->pictures.emplace_back();
    sc.picture = pictures[k];
    sc.slot = static_cast<std::int64_t>((platform.index() * 4 + static_cast<std::size_t>(side)) * 8 + k);
    sc.pass_camera = at_resolution(sc.picture.camera, options_.pass_width(), options_.pass_height());
    sc.clip_from_world = sc.pass_camera.clip_from_world();
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
    reach.box.extend(ndc_box(sc.clip_from_world, surface).box);
    for (const graph::ObjectId o : episode::everything_on(g_, initial, platform)) {
      reach.box.extend(ndc_box(sc.clip_from_world, boxes_[o.index()]).box);
    }
    int left = 0, top = 0, width = 0, height = 0;
    if (!reach.box.isEmpty()) {
      pixel_window(reach.box, sc.pass_camera.width, sc.pass_camera.height, left, top, width, height);
    }
    // Scenery that can cover none of the window (beside it in the picture, or behind all of it)
    // is left out: it changes none of the pixels the platform's objects can take.
    IdPass pass(sc.pass_camera, IdImage(left, top, width, height));
    for (const graph::ObjectId o : g_.objects.ids()) {
      if (g_.objects[o].pickable() || geometry_.of(o).indices.empty()) continue;
      if (!may_cover(ndc_box(sc.clip_from_world, boxes_[o.index()]), reach)) continue;
      add_silhouette(sc.silhouettes, o,
                     pass.draw(geometry_.of(o), object_pose(g_, initial, o), static_cast<std::int32_t>(o.index())));
    }
    sc.background = SceneryPixels(pass.take(), g_.objects.size() <= std::numeric_limits<std::int16_t>::max());
    for (const graph::ObjectId o : g_.objects.ids()) sc.initial_boxes.push_back(ndc_box(sc.clip_from_world, boxes_[o.index()]));
  }
  return out;
}

NdcBox VisibilityOracle::image_box(const episode::WorldState& s, graph::ObjectId o, const PictureScenery& sc) const {
  // Most objects stand where the graph found them: their image is known.
  if (s.objects[o].position == g_.objects[o].X_WO.translation()) return sc.initial_boxes[o.index()];
  return ndc_box(sc.clip_from_world, box_in(s, o));
}

VisibilityOracle::Deciders VisibilityOracle::deciders(const episode::WorldState& s, graph::PlatformId platform,
                                                      const PictureScenery& sc) const {
  // The platform's objects, and the items that may stand in front of them: nothing else changes
  // their pixels (the scenery is drawn already, and an item behind them or beside them in the
  // picture covers none of theirs).
  Deciders d;
  append_key(d.key, sc.slot);
  // The platform's objects in this picture: one wholly outside it (in another part of a long
  // platform) shows nothing here and covers nothing that does, so the picture does not depend on
  // where it stands.
  std::vector<std::pair<graph::ObjectId, NdcBox>> showing;
  for (const graph::ObjectId o : episode::everything_on(g_, s, platform)) {
    if (episode::carried(g_, s, o)) continue;
    NdcBox box = image_box(s, o, sc);
    if (box.box.isEmpty() && !box.anywhere) continue;
    showing.emplace_back(o, std::move(box));
  }
  std::sort(showing.begin(), showing.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<NdcBox> targets;
  Eigen::AlignedBox3f all;
  for (auto& [o, box] : showing) {
    d.on.push_back(o);
    all.extend(box.box);
    targets.push_back(std::move(box));
  }
  if (all.isEmpty()) return d;  // nothing on it to see
  for (const graph::ObjectId o : movable_) {
    if (episode::carried(g_, s, o)) continue;
    const bool own = std::binary_search(d.on.begin(), d.on.end(), o);
    if (!own) {
      const NdcBox b = image_box(s, o, sc);
      // Most items are nowhere near the platform's objects in the picture: one test for all.
      if (!may_cover(b, NdcBox{all, false})) continue;
      if (!std::any_of(targets.begin(), targets.end(), [&](const NdcBox& t) { return may_cover(b, t); })) continue;
    }
    d.items.push_back(o);
    const Eigen::Vector3d& at = s.objects[o].position;
    d.at.push_back(at);
    append_item(d.key, o, at);
  }
  pixel_window(all, sc.pass_camera.width, sc.pass_camera.height, d.left, d.top, d.width, d.height);
  return d;
}

bool VisibilityOracle::in_view(const episode::WorldState& s, graph::PlatformId platform, graph::ObjectId o) const {
  const int side = std::max(0, g_.platforms.at(platform).default_side);
  for (const PictureScenery& sc : scenery(platform, side).pictures) {
    const Deciders d = deciders(s, platform, sc);
    if (std::find(d.items.begin(), d.items.end(), o) != d.items.end()) return true;
  }
  return false;
}

std::string VisibilityOracle::view_key(const episode::WorldState& s, graph::PlatformId platform) const {
  const int side = std::max(0, g_.platforms.at(platform).default_side);
  std::string key;
  for (const PictureScenery& sc : scenery(platform, side).pictures) key += deciders(s, platform, sc).key;
  append_key(key, s.platform_offset.at(platform).x());
  append_key(key, s.platform_offset.at(platform).y());
  append_key(key, s.platform_offset.at(platform).z());
  return key;
}

std::shared_ptr<const ViewSight> VisibilityOracle::arrival_view(const episode::WorldState& s,
                                                                graph::PlatformId platform) const {
  return view(s, platform, std::max(0, g_.platforms.at(platform).default_side));
}

IdImage VisibilityOracle::draw_window(const PictureScenery& sc, const Deciders& d,
                                      std::vector<ObjectSight>& silhouettes) const {
  const SceneryPixels& bg = sc.background;
  std::optional<IdPass> pass;
  if (bg.holds(d.left, d.top, d.width, d.height)) {
    pass.emplace(sc.pass_camera, bg.window(d.left, d.top, d.width, d.height));
    for (const graph::ObjectId o : d.on) {
      if (g_.objects[o].pickable()) continue;
      const ObjectSight kept = sight_of(sc.silhouettes, o);
      if (kept.silhouette > 0) silhouettes.push_back(kept);
    }
  } else {
    // Something on the platform reaches out of the window drawn beforehand (an item placed
    // overhanging it): the scenery of this window is drawn afresh, the same pixels (scenery
    // stands where the graph found it).
    pass.emplace(sc.pass_camera, IdImage(d.left, d.top, d.width, d.height));
    for (const graph::ObjectId o : g_.objects.ids()) {
      if (g_.objects[o].pickable() || geometry_.of(o).indices.empty()) continue;
      const int pixels = pass->draw(geometry_.of(o), g_.objects[o].X_WO, static_cast<std::int32_t>(o.index()));
      if (std::binary_search(d.on.begin(), d.on.end(), o)) add_silhouette(silhouettes, o, pixels);
    }
  }
  IdImage image = pass->take();
  for (std::size_t k = 0; k < d.items.size(); ++k) {
    const graph::ObjectId o = d.items[k];
    const int pixels = composite(*splat(sc, o, d.at[k]), static_cast<std::int32_t>(o.index()), image);
    if (std::binary_search(d.on.begin(), d.on.end(), o)) add_silhouette(silhouettes, o, pixels);
  }
  std::sort(silhouettes.begin(), silhouettes.end(),
            [](const ObjectSight& a, const ObjectSight& b) { return a.object < b.object; });
  return image;
}

std::shared_ptr<const Splat> VisibilityOracle::splat(const PictureScenery& sc, graph::ObjectId o,
                                                     const Eigen::Vector3d& at) const {
  std::string key;
  append_key(key, sc.slot);
  append_item(key, o, at);
  return splats_.get(key, [&] {
    // Items move without turning (episode::place_held): the graph's pose moved to where it stands.
    const Eigen::Isometry3d pose = Eigen::Translation3d(at - g_.objects[o].X_WO.translation()) * g_.objects[o].X_WO;
    return std::make_shared<const Splat>(splat_of(sc.pass_camera, geometry_.of(o), pose));
  });
}

std::shared_ptr<const std::vector<ObjectSight>> VisibilityOracle::picture_counts(const PictureScenery& sc,
                                                                                const Deciders& d) const {
  return picture_sights_.get(d.key, [&] {
    const std::shared_ptr<const Window> w = window(sc, d);
    return std::make_shared<const std::vector<ObjectSight>>(count_pixels(w->image, w->silhouettes));
  });
}

std::shared_ptr<const ViewSight> VisibilityOracle::view(const episode::WorldState& s, graph::PlatformId platform,
                                                        int side) const {
  MTG_DEMAND(side >= 0 && side <= 3, "visibility: side out of range");
  if (!s.platform_offset.at(platform).isZero()) {
    // A platform that moved with its item: no scenery drawing fits it; draw it all.
    std::vector<ViewSight::Picture> pictures;
    for (const PlatformPicture& picture :
         platform_pictures(g_, s, platform, side, options_.image_width, options_.image_height)) {
      IdView v = draw_id_view(g_, geometry_, s,
                              at_resolution(picture.camera, options_.pass_width(), options_.pass_height()));
      pictures.push_back({picture.camera, std::move(v.objects)});
    }
    return std::make_shared<const ViewSight>(std::move(pictures), options_);
  }
  const Scenery& sc = scenery(platform, side);
  // Each picture is counted when first asked about (most questions are settled by the first),
  // and its counts are remembered by its own deciders.
  std::vector<Camera> cameras;
  std::vector<ViewSight::Count> counts;
  for (const PictureScenery& picture : sc.pictures) {
    cameras.push_back(picture.picture.camera);
    counts.push_back([this, p = &picture, d = deciders(s, platform, picture)] { return picture_counts(*p, d); });
  }
  return std::make_shared<const ViewSight>(std::move(cameras), std::move(counts), options_);
}

std::shared_ptr<const VisibilityOracle::Window> VisibilityOracle::window(const PictureScenery& sc,
                                                                         const Deciders& d) const {
  return windows_.get(d.key, [&] {
    auto w = std::make_shared<Window>();
    w->image = draw_window(sc, d, w->silhouettes);
    return std::shared_ptr<const Window>(std::move(w));
  });
}

std::vector<graph::ObjectId> showing_in(const std::vector<ObjectSight>& sights) {
  std::vector<graph::ObjectId> out;
  for (const ObjectSight& o : sights) {
    if (o.visible > 0) out.push_back(graph::ObjectId::of_index(static_cast<std::size_t>(o.object)));
  }
  return out;
}

IdImage VisibilityOracle::whole_pass(const PictureScenery& sc, const Deciders& d) const {
  // The numbered objects are all inside the window, and their pixels there are those of a whole
  // pass: laid out on it, the marks go where the renderer puts them.
  const std::shared_ptr<const Window> w = window(sc, d);
  IdImage out(sc.pass_camera.width, sc.pass_camera.height);
  for (int v = 0; v < w->image.height; ++v) {
    for (int u = 0; u < w->image.width; ++u) {
      out.ids[static_cast<std::size_t>(w->image.top + v) * static_cast<std::size_t>(out.width) +
              static_cast<std::size_t>(w->image.left + u)] = w->image.at(u, v);
    }
  }
  return out;
}

bool VisibilityOracle::mark_readable(const episode::WorldState& s, graph::PlatformId platform, graph::ObjectId o) const {
  const int side = std::max(0, g_.platforms.at(platform).default_side);
  const auto index = static_cast<std::int32_t>(o.index());
  const std::vector<ItemMark> all_items = item_marks(g_, s, platform);
  if (!s.platform_offset.at(platform).isZero()) {
    for (const PlatformPicture& picture :
         platform_pictures(g_, s, platform, side, options_.image_width, options_.image_height)) {
      const IdView whole =
          draw_id_view(g_, geometry_, s, at_resolution(picture.camera, options_.pass_width(), options_.pass_height()));
      const std::vector<ItemMark> items =
          picture.part == 0 ? all_items : numbered_in(g_, s, platform, side, picture, all_items, showing_in(whole.objects));
      const std::vector<std::int32_t> readable = readable_marks(s, items, picture.camera, whole.image);
      if (std::binary_search(readable.begin(), readable.end(), index)) return true;
    }
    return false;
  }
  // First each picture itself (most marks have their place there); only then the zooms of those
  // that left the mark crowded (drawn anew: the costly part). The answer does not depend on the order.
  struct Crowded {
    const PictureScenery* sc;
    Deciders d;
    std::vector<ItemMark> items;
    std::string key;
  };
  std::vector<Crowded> crowded;
  for (const PictureScenery& sc : scenery(platform, side).pictures) {
    Deciders d = deciders(s, platform, sc);
    std::vector<ItemMark> items = all_items;
    if (sc.picture.part != 0) {  // the counts are remembered longer than the window's pixels
      items = numbered_in(g_, s, platform, side, sc.picture, all_items, showing_in(*picture_counts(sc, d)));
    }
    if (std::none_of(items.begin(), items.end(), [&](const ItemMark& m) { return m.object == o; })) continue;
    // The items' numbers (their order on the platform) decide where their marks go too.
    std::string key = d.key;
    for (const ItemMark& m : items) {
      append_key(key, static_cast<std::int64_t>(m.object.index()));
      append_key(key, static_cast<std::int64_t>(m.number));
    }
    // The picture itself first: most marks have their place there, and the zooms (drawn anew)
    // are worked out only for a mark that has not.
    const std::shared_ptr<const MarksInPicture> main = in_picture_.get(key, [&] {
      const MarkLayout layout = layout_item_marks(whole_pass(sc, d), kMarkPassScale, sc.picture.camera, items);
      auto m = std::make_shared<MarksInPicture>();
      for (const PlacedMark& p : layout.placed) m->placed.push_back(static_cast<std::int32_t>(p.object.index()));
      for (const ItemMark& c : layout.crowded) m->crowded.push_back(static_cast<std::int32_t>(c.object.index()));
      std::sort(m->placed.begin(), m->placed.end());
      std::sort(m->crowded.begin(), m->crowded.end());
      return std::shared_ptr<const MarksInPicture>(std::move(m));
    });
    if (std::binary_search(main->placed.begin(), main->placed.end(), index)) return true;
    if (std::binary_search(main->crowded.begin(), main->crowded.end(), index)) {
      crowded.push_back({&sc, std::move(d), std::move(items), std::move(key)});
    }
  }
  for (const Crowded& c : crowded) {
    const std::shared_ptr<const std::vector<std::int32_t>> readable = with_zooms_.get(c.key, [&] {
      return std::make_shared<const std::vector<std::int32_t>>(
          readable_marks(s, c.items, c.sc->picture.camera, whole_pass(*c.sc, c.d)));
    });
    if (std::binary_search(readable->begin(), readable->end(), index)) return true;
  }
  return false;
}

}  // namespace mtg::render
