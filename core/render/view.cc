#include "core/render/view.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/graph/standing.h"
#include "core/util/error.h"

namespace mtg::render {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kFocus = 0.86;               // key points fill at most this share of the image
constexpr double kMinFovy = 20.0 * kPi / 180;
constexpr double kMaxFovy = 100.0 * kPi / 180;
constexpr double kStepBack = 0.25;            // metres per step when even kMaxFovy is too narrow
constexpr int kMaxStepsBack = 8;
constexpr double kMinSpan = 0.6;              // metres of surroundings around a small platform
constexpr double kCloseUpFovy = 40.0 * kPi / 180;
constexpr double kPartsFrom = 1.6;            // m across the view: longer platforms get part pictures
constexpr double kPartLength = 1.0;           // m of platform per part, about
constexpr int kMaxParts = 3;

// Bad requests are the caller's input, not our invariants: a plain one-line error.
void require(bool condition, const std::string& message) {
  if (!condition) throw Error(message);
}

struct Tangents {
  Eigen::AlignedBox2d box;  // of (x / -z, y / -z) in the camera frame
  bool behind = false;      // some key point is behind the camera
};

Tangents tangents(const Eigen::Isometry3d& X_WC, const std::vector<Eigen::Vector3d>& points) {
  Tangents t;
  const Eigen::Isometry3d X_CW = X_WC.inverse();
  for (const auto& p : points) {
    const Eigen::Vector3d c = X_CW * p;
    if (-c.z() < 0.02) {
      t.behind = true;
      continue;
    }
    t.box.extend(Eigen::Vector2d(c.x() / -c.z(), c.y() / -c.z()));
  }
  return t;
}

// Aims a camera at `eye` so `points` are centred and picks the field of view that holds them.
// Returns false when no field of view up to kMaxFovy can.
bool aim(const Eigen::Vector3d& eye, const Eigen::Vector3d& target, const std::vector<Eigen::Vector3d>& points,
         double aspect, Eigen::Isometry3d& X_WC, double& fovy) {
  X_WC = look_at(eye, target);
  for (int i = 0; i < 3; ++i) {  // the centre moves a little as the aim does; three rounds settle it
    const Tangents t = tangents(X_WC, points);
    if (t.box.isEmpty()) return false;
    const Eigen::Vector2d c = t.box.center();
    const Eigen::Vector3d forward = X_WC.linear() * Eigen::Vector3d(c.x(), c.y(), -1.0);
    X_WC = look_at(eye, eye + forward);
  }
  const Tangents t = tangents(X_WC, points);
  if (t.behind || t.box.isEmpty()) return false;
  const Eigen::Vector2d half = t.box.sizes() / 2.0;
  const double need = std::max(half.y(), half.x() / aspect) / kFocus;
  fovy = std::max(kMinFovy, 2.0 * std::atan(need));
  // Close to a wide platform the aim need not settle in three rounds, and a lens sized by the
  // box's half-width then cuts off its far side (an end of a TV stand, its free spaces drawn up
  // to 113 px left of the picture): such a lens is widened to hold the box as it lies. A lens
  // that holds it already is kept as it was.
  const double reach = std::max({-t.box.min().x() / aspect, t.box.max().x() / aspect, -t.box.min().y(), t.box.max().y()});
  if (reach > std::tan(fovy / 2.0)) fovy = std::max(fovy, 2.0 * std::atan(reach / kFocus));
  return fovy <= kMaxFovy;
}

// The world xy where the robot stands on `side` of `platform` (moved item platforms move along).
Eigen::Vector2d standing_point(const graph::SceneGraph& g, const episode::WorldState& s, graph::PlatformId platform,
                               int side) {
  const graph::Platform& p = g.platforms[platform];
  const graph::SideInfo& info = p.sides[static_cast<std::size_t>(side)];
  const Eigen::Vector2d shift = s.platform_offset[platform].head<2>();
  if (info.standing_area > 0.0) return info.standing_point + shift;
  if (!info.strip_W.empty()) {  // nowhere to stand: look from the middle of that side's strip
    Eigen::Vector2d c = Eigen::Vector2d::Zero();
    for (const auto& q : info.strip_W) c += q;
    return c / static_cast<double>(info.strip_W.size()) + shift;
  }
  // No strip either (a platform the graph never measured): one metre out from the named side.
  static const Eigen::Vector2d kOut[4] = {{0, -1}, {-1, 0}, {0, 1}, {1, 0}};
  const Eigen::Isometry2d X_WP = episode::platform_frame(g, s, platform);
  const Eigen::Vector2d half = p.box_P.sizes() / 2.0;
  const Eigen::Vector2d out = kOut[side];
  return X_WP * Eigen::Vector2d(out.x() * (half.x() + 1.0), out.y() * (half.y() + 1.0));
}

// Which way is right for a robot on `side` of a platform, in the platform frame P.
Eigen::Vector2d viewer_right(int side) {
  static const Eigen::Vector2d kRight[4] = {{1, 0}, {0, -1}, {-1, 0}, {0, 1}};
  return kRight[side];
}

// Where a camera at `stand` (eyes at `eye_z`) sees `keys` best: aimed at their middle, with the
// narrowest lens that holds them, stepping back from `centre` when even the widest cannot.
Camera frame_keys(const std::vector<Eigen::Vector3d>& keys, const Eigen::Vector2d& stand, const Eigen::Vector2d& centre,
                  double eye_z, int width, int height) {
  Eigen::Vector2d away = stand - centre;
  away = away.norm() > 1e-6 ? away.normalized() : Eigen::Vector2d(0, -1);
  Eigen::Vector3d target = Eigen::Vector3d::Zero();
  for (const auto& k : keys) target += k;
  target /= static_cast<double>(keys.size());
  Camera cam;
  cam.width = width;
  cam.height = height;
  for (int step = 0; step <= kMaxStepsBack; ++step) {
    const Eigen::Vector2d xy = stand + away * (kStepBack * step);
    const Eigen::Vector3d eye(xy.x(), xy.y(), eye_z);
    if (aim(eye, target, keys, cam.aspect(), cam.X_WC, cam.fovy)) break;
    cam.fovy = kMaxFovy;  // the last step keeps the widest lens
  }
  return cam;
}

// The pictures of a platform view, planned in the layout state `s`: the whole platform, then its
// parts when it is too long for one picture.
std::vector<PlatformPicture> plan_platform_pictures(const graph::SceneGraph& g, const episode::WorldState& s,
                                                    graph::PlatformId platform, int side, int width, int height) {
  const graph::Platform& p = g.platforms[platform];
  const double h = episode::platform_height(g, s, platform);
  const Eigen::Isometry2d X_WP = episode::platform_frame(g, s, platform);
  const Eigen::Isometry2d X_PW = X_WP.inverse();
  const Eigen::Vector2d right = viewer_right(side);
  // Everything on the platform, each with where it stands across the view (u, in P).
  struct Thing {
    const episode::ObjectState* state;
    double u;
    bool direct;
  };
  std::vector<Thing> things;
  const std::vector<graph::ObjectId>& direct = episode::objects_on(s, platform);
  for (const graph::ObjectId o : episode::everything_on(g, s, platform)) {
    const episode::ObjectState& st = s.objects[o];
    const bool is_direct = std::find(direct.begin(), direct.end(), o) != direct.end();
    things.push_back({&st, (X_PW * episode::footprint_centre(st)).dot(right), is_direct});
  }
  // The key points and the tallest top of what stands within [lo, hi) across the view.
  auto keys_of = [&](double lo, double hi, std::vector<Eigen::Vector3d>& keys, double& top) {
    top = h;
    for (const Thing& t : things) {
      if (t.u < lo || t.u >= hi) continue;
      top = std::max(top, t.state->top);
      if (!t.direct) continue;
      for (const auto& q : t.state->footprint) {
        keys.emplace_back(q.x(), q.y(), t.state->bottom);
        keys.emplace_back(q.x(), q.y(), t.state->top);
      }
    }
  };

  std::vector<PlatformPicture> out;
  {
    std::vector<Eigen::Vector3d> keys;
    for (const geom::Ring& ring : geom::transform(p.polygon_P, X_WP).rings) {
      for (const auto& q : ring) keys.emplace_back(q.x(), q.y(), h);
    }
    double top = h;
    keys_of(-std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(), keys, top);
    // A small surface (a stool, a bin lid) is shown with some of its surroundings, so the agent
    // can tell where it is: the key points span at least kMinSpan around the platform's centre.
    const Eigen::Vector2d mid = X_WP.translation();
    for (const Eigen::Vector2d& corner : {Eigen::Vector2d(-1, -1), Eigen::Vector2d(1, -1), Eigen::Vector2d(1, 1),
                                         Eigen::Vector2d(-1, 1)}) {
      const Eigen::Vector2d q = mid + corner * (kMinSpan / 2.0);
      keys.emplace_back(q.x(), q.y(), h);
    }
    PlatformPicture whole;
    whole.camera = frame_keys(keys, standing_point(g, s, platform, side), X_WP.translation(),
                              graph::eye_height(p, h, top), width, height);
    whole.lo = -std::numeric_limits<double>::infinity();
    whole.hi = std::numeric_limits<double>::infinity();
    out.push_back(whole);
  }
  // A platform longer than one picture shows well (a kitchen counter) gets a picture of each
  // part that holds something, seen from in front of that part (SideInfo::stands).
  const double extent = std::abs(p.box_P.sizes().dot(right));
  if (extent < kPartsFrom || things.empty()) return out;
  const int parts = std::min(kMaxParts, std::max(2, static_cast<int>(std::lround(extent / kPartLength))));
  const graph::SideInfo& info = p.sides[static_cast<std::size_t>(side)];
  const Eigen::Vector2d shift = s.platform_offset[platform].head<2>();
  const double u0 = -extent / 2.0;
  const double along = p.box_P.center().dot(right);
  const Eigen::Vector2d depth(right.y(), -right.x());  // across the view's other axis
  const double dmin = std::min((p.box_P.min()).dot(depth), (p.box_P.max()).dot(depth));
  const double dmax = std::max((p.box_P.min()).dot(depth), (p.box_P.max()).dot(depth));
  for (int k = 0; k < parts; ++k) {
    const double lo = along + u0 + extent * k / parts, hi = along + u0 + extent * (k + 1) / parts;
    std::vector<Eigen::Vector3d> keys;
    double top = h;
    keys_of(k == 0 ? -std::numeric_limits<double>::infinity() : lo,
            k + 1 == parts ? std::numeric_limits<double>::infinity() : hi, keys, top);
    if (keys.empty()) continue;  // nothing stands there
    for (const double u : {lo, hi}) {
      for (const double d : {dmin, dmax}) {
        const Eigen::Vector2d q = X_WP * (right * u + depth * d);
        keys.emplace_back(q.x(), q.y(), h);
      }
    }
    const Eigen::Vector2d centre = X_WP * (right * ((lo + hi) / 2.0) + depth * ((dmin + dmax) / 2.0));
    Eigen::Vector2d stand = standing_point(g, s, platform, side);
    double best = std::numeric_limits<double>::infinity();
    for (const geom::Point2& q : info.stands) {
      const double d = (q + shift - centre).squaredNorm();
      if (d < best) {
        best = d;
        stand = q + shift;
      }
    }
    PlatformPicture part;
    part.camera = frame_keys(keys, stand, centre, graph::eye_height(p, h, top), width, height);
    part.part = k + 1;
    part.parts = parts;
    part.lo = k == 0 ? -std::numeric_limits<double>::infinity() : lo;
    part.hi = k + 1 == parts ? std::numeric_limits<double>::infinity() : hi;
    out.push_back(part);
  }
  return out;
}

ViewPlan platform_view(const graph::SceneGraph& g, const episode::WorldState& s, const ViewRequest& r) {
  require(g.platforms.contains(r.platform), "render: platform index " + to_string(r.platform) + " out of range");
  const graph::Platform& p = g.platforms[r.platform];
  ViewPlan plan;
  plan.side = r.side;
  if (plan.side < 0) plan.side = s.at_platform == r.platform && s.side >= 0 ? s.side : std::max(0, p.default_side);
  require(plan.side <= 3, "render: side " + std::to_string(plan.side) + " is not 0..3");
  plan.camera = platform_camera(g, s, r.platform, plan.side, r.width, r.height);
  for (const graph::ObjectId h : episode::in_hand(g, s)) plan.hidden.push_back(h);  // not where it stood
  if (r.marks == MarkKind::kItems) plan.marks.items = item_marks(g, s, r.platform);
  if (r.marks == MarkKind::kTargets) {
    // One set of targets for the numbered regions and the lettered scenery they are named after.
    const std::vector<episode::PlaceTarget> targets =
        episode::place_targets(g, s, r.platform, static_cast<graph::Side>(plan.side), r.min_region_size);
    plan.marks.regions = target_marks(g, s, r.platform, targets);
    plan.marks.fixtures = fixture_marks(g, s, r.platform, targets);
  }
  return plan;
}

// An object's middle and the radius of a ball around it, for close-ups.
struct ObjectExtent {
  Eigen::Vector3d centre;
  double radius = 0.0;
};
ObjectExtent extent_of(const episode::ObjectState& o) {
  const geom::Point2 c2 = episode::footprint_centre(o);
  const Eigen::AlignedBox2d box = geom::bounds(o.footprint);
  return {Eigen::Vector3d(c2.x(), c2.y(), (o.bottom + o.top) / 2.0),
          0.5 * Eigen::Vector3d(box.sizes().x(), box.sizes().y(), o.top - o.bottom).norm()};
}

// A 40-degree camera on `target`, `distance` away towards the horizontal direction `from`,
// `elevation` above the horizon.
Camera close_up_camera(const Eigen::Vector3d& target, Eigen::Vector2d from, double distance, double elevation,
                       const ViewRequest& r) {
  from = from.norm() > 1e-6 ? from.normalized() : Eigen::Vector2d(0, -1);
  Camera cam;
  cam.width = r.width;
  cam.height = r.height;
  cam.fovy = kCloseUpFovy;
  const Eigen::Vector3d eye = target + distance * Eigen::Vector3d(std::cos(elevation) * from.x(),
                                                                  std::cos(elevation) * from.y(), std::sin(elevation));
  cam.X_WC = look_at(eye, target);
  return cam;
}

// The extent of `object` with what it carries: one box around them all.
ObjectExtent extent_with(const episode::WorldState& s, graph::ObjectId object, const std::vector<graph::ObjectId>& carried) {
  if (carried.empty()) return extent_of(s.objects[object]);
  Eigen::AlignedBox2d box = geom::bounds(s.objects[object].footprint);
  double bottom = s.objects[object].bottom, top = s.objects[object].top;
  for (const graph::ObjectId c : carried) {
    box.extend(geom::bounds(s.objects[c].footprint));
    bottom = std::min(bottom, s.objects[c].bottom);
    top = std::max(top, s.objects[c].top);
  }
  const Eigen::Vector2d c2 = box.center();
  return {Eigen::Vector3d(c2.x(), c2.y(), (bottom + top) / 2.0),
          0.5 * Eigen::Vector3d(box.sizes().x(), box.sizes().y(), top - bottom).norm()};
}

ViewPlan item_view(const graph::SceneGraph& g, const episode::WorldState& s, const ViewRequest& r) {
  require(g.objects.contains(r.object), "render: object index " + to_string(r.object) + " out of range");
  // Picked, what rests on it is carried along: the close-up shows the spice rack with its jars (a
  // rater saw an empty rack arrive full).
  const std::vector<graph::ObjectId> carried = episode::resting_on(g, s, r.object);
  const ObjectExtent e = extent_with(s, r.object, carried);
  const double radius = std::max(0.03, e.radius);
  // Seen from where the robot stands when it stands somewhere, else from the south-west.
  Eigen::Vector2d from(-1.0, -1.0);
  if (s.at_platform.valid() && s.side >= 0) from = standing_point(g, s, s.at_platform, s.side) - e.centre.head<2>();
  const double distance = radius / std::tan(kCloseUpFovy / 2.0) / 0.7;
  ViewPlan plan;
  plan.camera = close_up_camera(e.centre, from, distance, 30.0 * kPi / 180, r);
  plan.camera.near = std::max(0.01, distance - 2.0 * radius);
  plan.camera.far = distance + 2.0 * radius;
  plan.only = r.object;
  plan.only_with = carried;
  plan.numbered = {r.number, r.object, extent_of(s.objects[r.object]).centre};
  return plan;
}

ViewPlan focus_view(const graph::SceneGraph& g, const episode::WorldState& s, const ViewRequest& r) {
  require(g.objects.contains(r.object), "render: object index " + to_string(r.object) + " out of range");
  const graph::PlatformId platform = episode::furniture_platform_of(g, s, r.object);
  require(platform.valid(), "render: object " + g.objects[r.object].name +
                             " stands on no platform to show it on");
  const graph::Platform& p = g.platforms[platform];
  const episode::ObjectState& o = s.objects[r.object];
  const ObjectExtent e = extent_of(o);
  // The object and a hand's breadth around it, so its neighbours show (faded) for context.
  // Wide enough for its neighbours to show (faded), so a person sees where it stands among its
  // look-alikes (the third book of a row), not the object alone.
  const double radius = std::max(0.25, 3.0 * e.radius);
  const double distance = radius / std::tan(kCloseUpFovy / 2.0);
  // Looking down a little, but under the layer above an interior shelf.
  double elevation = 35.0 * kPi / 180;
  if (std::isfinite(p.clearance)) {
    const double headroom = episode::platform_height(g, s, platform) + p.clearance - 0.02 - e.centre.z();
    elevation = std::clamp(std::asin(std::clamp(headroom / distance, -1.0, 1.0)), 0.0, elevation);
  }
  ViewPlan plan;
  // From where the robot stands when it is at that platform, else from where it arrives there.
  const int side = s.at_platform == platform && s.side >= 0 ? s.side : std::max(0, p.default_side);
  const Eigen::Vector2d from = standing_point(g, s, platform, side) - e.centre.head<2>();
  plan.camera = close_up_camera(e.centre, from, distance, elevation, r);
  plan.camera.near = std::max(0.01, distance - 3.0 * radius);
  plan.camera.far = distance + 6.0;
  // Every other item fades, what it rests on too (a book on a book must not look like two
  // answers), so only this one stands out.
  const std::vector<graph::ObjectId> beside = episode::everything_on(g, s, platform);
  for (const graph::ObjectId other : g.objects.ids()) {
    const bool on_platform = std::find(beside.begin(), beside.end(), other) != beside.end();
    if (other != r.object && (g.objects[other].pickable() || on_platform)) plan.faded.push_back(other);
  }
  for (const graph::ObjectId h : episode::in_hand(g, s)) plan.hidden.push_back(h);  // not where it stood
  plan.numbered = {r.number, r.object, e.centre};
  return plan;
}

ViewPlan topdown_view(const graph::SceneGraph& g, const episode::WorldState& s, const ViewRequest& r) {
  Eigen::AlignedBox2d box;
  double top = 0.0;
  for (const graph::ObjectId i : g.objects.ids()) {
    const graph::ObjectKind kind = g.objects[i].kind;
    if (kind == graph::ObjectKind::kUnsupported || episode::carried(g, s, i)) continue;
    for (const auto& q : s.objects[i].footprint) box.extend(q);
    top = std::max(top, s.objects[i].top);
  }
  require(!box.isEmpty(), "render: the scene has no objects to look down on");
  ViewPlan plan;
  Camera& cam = plan.camera;
  cam.width = r.width;
  cam.height = r.height;
  cam.orthographic = true;
  const Eigen::Vector2d c = box.center();
  const Eigen::Vector2d half = box.sizes() / 2.0;
  // The scene's long side goes along the image's long side: a tall apartment in a wide image
  // would otherwise fill ~40 % of it and its labels would crowd. Turned, east is up; no text the
  // agent reads names a compass direction, and the marks are drawn after the turn.
  const bool turn = (half.y() > half.x()) != (cam.height > cam.width);
  const double across = turn ? half.y() : half.x(), along = turn ? half.x() : half.y();
  cam.ortho_half_height = 1.04 * std::max(along, across / cam.aspect());
  cam.X_WC = look_at(Eigen::Vector3d(c.x(), c.y(), top + 2.0), Eigen::Vector3d(c.x(), c.y(), 0.0),
                     turn ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY());
  cam.near = 0.1;
  cam.far = top + 3.0;
  for (const graph::ObjectId h : episode::in_hand(g, s)) plan.hidden.push_back(h);  // not where it stood
  if (r.marks == MarkKind::kLabels) plan.marks.labels = platform_labels(g, s);
  return plan;
}

}  // namespace

std::vector<PlatformPicture> platform_pictures(const graph::SceneGraph& g, const episode::WorldState& s,
                                               graph::PlatformId platform, int side, int width, int height) {
  require(g.platforms.contains(platform), "render: platform index " + to_string(platform) + " out of range");
  require(side >= 0 && side <= 3, "render: side " + std::to_string(side) + " is not 0..3");
  require_image_size(width, height);
  // Planned in the scene as the graph found it, so the view holds still while items come and go;
  // a platform that moved (one on an item) takes its cameras along.
  std::vector<PlatformPicture> out =
      plan_platform_pictures(g, episode::initial_state(g), platform, side, width, height);
  for (PlatformPicture& picture : out) picture.camera.X_WC.pretranslate(s.platform_offset[platform]);
  return out;
}

Camera platform_camera(const graph::SceneGraph& g, const episode::WorldState& s, graph::PlatformId platform, int side,
                       int width, int height) {
  return platform_pictures(g, s, platform, side, width, height).front().camera;
}

namespace {

bool in_part_at(const graph::SceneGraph& g, const episode::WorldState& s, graph::PlatformId platform, int side,
                const PlatformPicture& picture, const Eigen::Vector2d& xy_W) {
  if (picture.part == 0) return true;
  const Eigen::Isometry2d X_PW = episode::platform_frame(g, s, platform).inverse();
  const double u = (X_PW * xy_W).dot(viewer_right(side));
  return u >= picture.lo && u < picture.hi;
}

}  // namespace

bool in_picture_part(const graph::SceneGraph& g, const episode::WorldState& s, graph::PlatformId platform, int side,
                     const PlatformPicture& picture, graph::ObjectId object) {
  return in_part_at(g, s, platform, side, picture, episode::footprint_centre(s.objects[object]));
}

std::vector<RegionMark> regions_in(const graph::SceneGraph& g, const episode::WorldState& s, graph::PlatformId platform,
                                   int side, const PlatformPicture& picture, const std::vector<RegionMark>& regions) {
  std::vector<RegionMark> out;
  for (const RegionMark& r : regions) {
    if (in_part_at(g, s, platform, side, picture, r.label_W.head<2>())) out.push_back(r);
  }
  return out;
}

std::vector<ItemMark> numbered_in(const graph::SceneGraph& g, const episode::WorldState& s, graph::PlatformId platform,
                                  int side, const PlatformPicture& picture, const std::vector<ItemMark>& items,
                                  const std::vector<graph::ObjectId>& showing) {
  if (picture.part == 0) return items;
  std::vector<ItemMark> out;
  for (const ItemMark& m : items) {
    if (std::find(showing.begin(), showing.end(), m.object) != showing.end() ||
        in_picture_part(g, s, platform, side, picture, m.object)) {
      out.push_back(m);
    }
  }
  return out;
}

std::string part_words(const PlatformPicture& picture) {
  if (picture.part == 0) return "the whole platform";
  if (picture.parts == 2) return picture.part == 1 ? "the left half" : "the right half";
  if (picture.parts == 3) return picture.part == 1 ? "the left part" : picture.part == 2 ? "the middle part" : "the right part";
  return "part " + std::to_string(picture.part) + " of " + std::to_string(picture.parts) + " from the left";
}

const char* to_string(ViewKind kind) {
  switch (kind) {
    case ViewKind::kPlatform: return "platform";
    case ViewKind::kItem: return "item";
    case ViewKind::kFocus: return "focus";
    case ViewKind::kTopdown: return "topdown";
  }
  return "platform";
}

const char* to_string(MarkKind kind) {
  switch (kind) {
    case MarkKind::kNone: return "";
    case MarkKind::kItems: return "items";
    case MarkKind::kTargets: return "targets";
    case MarkKind::kLabels: return "labels";
  }
  return "";
}

ViewKind parse_view_kind(const std::string& name) {
  if (name == "platform") return ViewKind::kPlatform;
  if (name == "item") return ViewKind::kItem;
  if (name == "focus") return ViewKind::kFocus;
  if (name == "topdown") return ViewKind::kTopdown;
  throw Error("render: unknown view '" + name + "' (platform, item, focus or topdown)");
}

MarkKind parse_mark_kind(const std::string& name) {
  if (name.empty() || name == "none") return MarkKind::kNone;
  if (name == "items") return MarkKind::kItems;
  if (name == "targets") return MarkKind::kTargets;
  if (name == "labels") return MarkKind::kLabels;
  throw Error("render: unknown marks '" + name + "' (items, targets, labels or none)");
}

void require_image_size(int width, int height) {
  require(width > 0 && height > 0 && width <= 8192 && height <= 8192,
          "render: image size " + std::to_string(width) + "x" + std::to_string(height) + " is not in 1..8192");
}

ViewPlan plan_view(const graph::SceneGraph& g, const episode::WorldState& s, const ViewRequest& request) {
  require_image_size(request.width, request.height);
  switch (request.view) {
    case ViewKind::kPlatform: return platform_view(g, s, request);
    case ViewKind::kItem: return item_view(g, s, request);
    case ViewKind::kFocus: return focus_view(g, s, request);
    case ViewKind::kTopdown: return topdown_view(g, s, request);
  }
  throw Error("render: unknown view kind");
}

std::vector<ViewRequest> observation_views(const episode::WorldState& s, int width, int height,
                                           double min_region_size) {
  std::vector<ViewRequest> out;
  ViewRequest base;
  base.width = width;
  base.height = height;
  base.min_region_size = min_region_size;
  switch (s.phase) {
    case episode::Phase::kDone: return out;
    case episode::Phase::kStart: {
      ViewRequest r = base;
      r.view = ViewKind::kTopdown;
      r.marks = MarkKind::kLabels;
      out.push_back(r);
      break;
    }
    case episode::Phase::kAtPlatform:
    case episode::Phase::kPlacing: {
      ViewRequest r = base;
      r.view = ViewKind::kPlatform;
      r.platform = s.at_platform;
      r.side = s.side;
      r.marks = s.phase == episode::Phase::kPlacing ? MarkKind::kTargets : MarkKind::kItems;
      out.push_back(r);
      break;
    }
  }
  if (s.held.valid()) {
    ViewRequest r = base;
    r.view = ViewKind::kItem;
    r.object = s.held;
    out.push_back(r);
  }
  return out;
}

Eigen::Isometry3d object_pose(const graph::SceneGraph& g, const episode::WorldState& s, graph::ObjectId i) {
  const graph::GraphObject& o = g.objects[i];
  const Eigen::Vector3d moved = s.objects[i].position - o.X_WO.translation();
  return Eigen::Translation3d(moved) * o.X_WO;
}

}  // namespace mtg::render
