#pragma once
// Where the camera goes for each kind of image the agent receives, and what the image shows
// (docs/render.md, "Views"). Pure geometry of the scene graph and a world state; no GL.
//
//   platform  from the robot's standing point on one side of a platform, at eye height above
//             the tallest item, aimed and zoomed so the whole surface and its items are in view
//             (closed form: aim at the angular centre of the key points, then the field of view
//             that holds them, stepping back when even a wide lens cannot)
//   item      a close-up of one object alone (the held item), seen from the robot's side
//   focus     a close-up of one object where it stands, seen from its platform's arrival side,
//             with every other item faded to 20 % (the paper's task-provided image of an object
//             that has look-alikes, official-impl-spec §7.4); what it rests on stays solid
//   topdown   an orthographic overview of the whole scene, its long side along the image's

#include <string>
#include <vector>

#include "core/episode/world_state.h"
#include "core/render/camera.h"
#include "core/render/marks.h"

namespace mtg::render {

enum class ViewKind { kPlatform, kItem, kFocus, kTopdown };
enum class MarkKind { kNone, kItems, kTargets, kLabels };

/// "platform", "item", "focus", "topdown" / "", "items", "targets", "labels".
/// @throws mtg::Error otherwise.
ViewKind parse_view_kind(const std::string& name);
MarkKind parse_mark_kind(const std::string& name);
const char* to_string(ViewKind kind);
const char* to_string(MarkKind kind);  // "" for kNone

struct ViewRequest {
  ViewKind view = ViewKind::kPlatform;
  graph::PlatformId platform;  // platform views
  int side = -1;       // -1: where the robot stands if it is at that platform, else the default side
  graph::ObjectId object;      // item and focus views
  MarkKind marks = MarkKind::kNone;
  int width = 640;
  int height = 480;
  double min_region_size = 0.03;  // as episode::RuleOptions, for target numbering
  int number = 0;                 // item and focus views: the number drawn on the object (0: none)
  std::string caption;            // the asker's words for the image
};

/// How much of a faded object shows through (the release dims neighbours to 20 %).
inline constexpr double kFadedVisibility = 0.2;

struct ViewPlan {
  Camera camera;
  int side = -1;             // the side used (platform views)
  std::vector<graph::ObjectId> hidden;  // objects not drawn (the held item stays out of scene views)
  graph::ObjectId only;                 // when valid, the single object drawn (item close-ups)...
  std::vector<graph::ObjectId> only_with;  // ... with what it carries (resting on it)
  std::vector<graph::ObjectId> faded;   // drawn at kFadedVisibility (focus close-ups: the neighbours)
  Marks marks;
  ItemMark numbered;  // a close-up's object with its number drawn on it (number 0: none)
  std::size_t first_zoom = 0;  // the name of its first zoom: Z<first_zoom + 1>
};

/// @throws mtg::Error unless 1 <= width, height <= 8192 (checked before any work).
void require_image_size(int width, int height);

/// @throws mtg::Error naming the problem (index out of range, non-positive size, ...).
ViewPlan plan_view(const graph::SceneGraph& g, const episode::WorldState& s, const ViewRequest& request);

/// One picture of a platform view: the whole platform, or one part of a platform too long for a
/// single picture (a kitchen counter), seen from in front of that part.
struct PlatformPicture {
  Camera camera;
  int part = 0;   // 0: the whole platform; k >= 1: the k-th of `parts` parts, from the viewer's left
  int parts = 0;  // how many parts the platform is cut into (0 for the whole)
  // What the part holds: objects whose footprint centre lies in [lo, hi) along the viewer's right,
  // in the platform frame (unbounded for the whole and at the ends).
  double lo = 0.0, hi = 0.0;
};

/// The pictures of the platform view from `side` at `width` x `height`: the whole platform
/// (platform_camera), then, for a platform more than 1.6 m across the view, one picture of
/// each part (about a metre, at most three) that holds something, from the place along the side
/// nearest that part (graph::SideInfo::stands). Planned in the scene as the graph found it, like
/// the camera; the agent gets them all when it arrives, and what it can see is decided on them.
/// @throws mtg::Error for a bad platform, side or size.
std::vector<PlatformPicture> platform_pictures(const graph::SceneGraph& g, const episode::WorldState& s,
                                               graph::PlatformId platform, int side, int width, int height);

/// Whether `object` (on `platform` in `s`) belongs to `picture`'s part: it numbers these, and
/// whatever else shows in it.
bool in_picture_part(const graph::SceneGraph& g, const episode::WorldState& s, graph::PlatformId platform, int side,
                     const PlatformPicture& picture, graph::ObjectId object);

/// The item marks `picture` numbers: all of `items` for the whole platform; for a part, the items
/// of that part and every other that shows in it (`showing`: the objects with pixels in it).
std::vector<ItemMark> numbered_in(const graph::SceneGraph& g, const episode::WorldState& s, graph::PlatformId platform,
                                  int side, const PlatformPicture& picture, const std::vector<ItemMark>& items,
                                  const std::vector<graph::ObjectId>& showing);

/// The placement targets `picture` numbers: those whose number stands in its part (all of them for
/// the whole platform).
std::vector<RegionMark> regions_in(const graph::SceneGraph& g, const episode::WorldState& s, graph::PlatformId platform,
                                   int side, const PlatformPicture& picture, const std::vector<RegionMark>& regions);

/// "the whole platform", "the left half", "the middle part", ...
std::string part_words(const PlatformPicture& picture);

/// The camera of the platform view from `side` (0..3) at `width` x `height`. It is planned in the
/// scene as the graph found it and does not move while items are picked and placed (docs/render.md,
/// "Views"), so the agent's view of a platform, and what can be seen in it, depends on the
/// platform and side only: the arrival view of a platform is this camera at its default side.
/// @throws mtg::Error for a bad platform, side or size.
Camera platform_camera(const graph::SceneGraph& g, const episode::WorldState& s, graph::PlatformId platform, int side,
                       int width, int height);

/// The images an observation in state `s` carries (docs/render.md, "What the agent sees"):
///   start            the overview with every platform's l<N>
///   at a platform    the platform from where the robot stands, items numbered o<N>
///   placing          the same view with the placement targets numbered as their keys
///   holding          plus a close-up of the item in hand
///   done             nothing
std::vector<ViewRequest> observation_views(const episode::WorldState& s, int width, int height,
                                           double min_region_size);

/// The world pose of object `o` in state `s` (its settled pose moved as the episode moved it).
Eigen::Isometry3d object_pose(const graph::SceneGraph& g, const episode::WorldState& s, graph::ObjectId o);

}  // namespace mtg::render
