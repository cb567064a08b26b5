#pragma once
// What the agent can see of a platform when it arrives there (the platform view from the side
// `l<N>` brings it to), from the CPU id pass of that view: how many pixels of each object show,
// against how many it would cover with nothing in front of it. Task generation names and counts
// only objects that are clearly visible in that view (docs/tasks.md, "Seen, not only there"),
// and the thresholds are in pixels of the image the agent gets.
//
// The camera of a platform view does not depend on the state (view.h, platform_camera), so the
// scenery of each platform's view is drawn once; a state adds only the items in the view. A
// view is remembered by the exact positions of the items it shows, so a state whose items in
// view stand where they stood gets the same answer, bit for bit, from any thread.

#include <algorithm>
#include <functional>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "core/episode/world_state.h"
#include "core/render/camera.h"
#include "core/render/id_raster.h"
#include "core/render/marks.h"
#include "core/render/scene_geometry.h"
#include "core/render/visibility_options.h"
#include "core/util/memo_table.h"

namespace mtg::render {

/// Pixels of one object in one view, counted in the id pass.
struct ObjectSight {
  std::int32_t object = -1;  // graph object index
  int visible = 0;           // pixels that show it
  int silhouette = 0;        // pixels it would cover with nothing in front of it
  double share() const { return silhouette > 0 ? static_cast<double>(visible) / silhouette : 0.0; }
};

/// What a view shows of a platform's objects (and of whatever else it drew), by object index:
/// one picture, or the several pictures of a long platform's view (view.h, platform_pictures),
/// of which an object needs to show clearly in one.
class ViewSight {
 public:
  struct Picture {
    Camera camera;                    // at the agent's image size
    std::vector<ObjectSight> objects; // sorted by object index
  };
  /// Counts a picture's objects when it is first asked about (the oracle's pictures: most
  /// questions are settled by the first picture).
  using Count = std::function<std::shared_ptr<const std::vector<ObjectSight>>()>;

  ViewSight(Camera image_camera, std::vector<ObjectSight> objects, const VisibilityOptions& options);
  ViewSight(std::vector<Picture> pictures, const VisibilityOptions& options);
  /// Pictures counted on demand, each once (thread-safe); `counts[k]` belongs to `cameras[k]`.
  ViewSight(std::vector<Camera> cameras, std::vector<Count> counts, const VisibilityOptions& options);
  ~ViewSight();
  ViewSight(const ViewSight&) = delete;
  ViewSight& operator=(const ViewSight&) = delete;

  /// The object's pixels in the picture that shows most of it (zero when none shows it).
  ObjectSight of(graph::ObjectId o) const;
  /// The object's pixels in picture `k`.
  ObjectSight of(std::size_t k, graph::ObjectId o) const;
  /// Enough of it shows in some picture, and a large enough share of it, for a person to tell
  /// what it is.
  bool clearly_visible(graph::ObjectId o) const;
  bool clearly_visible_in(std::size_t k, graph::ObjectId o) const;
  /// Image pixels (at the agent's image size) showing the object, in the picture that shows most.
  double image_pixels(graph::ObjectId o) const;
  /// The same in picture `k`.
  double image_pixels_in(std::size_t k, graph::ObjectId o) const;

  std::size_t pictures() const { return pictures_.size(); }
  /// The camera of picture `k` (the agent's image size), for placing things in the picture.
  const Camera& camera(std::size_t k = 0) const;
  /// Picture k's objects, sorted by object index.
  const std::vector<ObjectSight>& objects(std::size_t k = 0) const;

 private:
  struct Slot;
  std::vector<std::unique_ptr<Slot>> pictures_;
  double pixel_area_ = 1.0;           // image pixels per pass pixel
  VisibilityOptions options_;
};

struct NdcBox;  // where a world box lands in the image (visibility.cc)

class VisibilityOracle {
 public:
  /// `g` and `geometry` must outlive the oracle.
  VisibilityOracle(const graph::SceneGraph& g, const SceneGeometry& geometry, VisibilityOptions options = {});
  ~VisibilityOracle();
  VisibilityOracle(const VisibilityOracle&) = delete;
  VisibilityOracle& operator=(const VisibilityOracle&) = delete;

  /// The arrival view of `platform` (its default side) in state `s`; the held item is not drawn.
  std::shared_ptr<const ViewSight> arrival_view(const episode::WorldState& s, graph::PlatformId platform) const;
  /// The same for any side.
  std::shared_ptr<const ViewSight> view(const episode::WorldState& s, graph::PlatformId platform, int side) const;
  /// Whether item `o`'s number has a readable place in the marked arrival view of `platform` in
  /// `s` or in one of its zoomed views (mark_layout.h), as the renderer lays the marks out; false
  /// for an object that view does not number.
  bool mark_readable(const episode::WorldState& s, graph::PlatformId platform, graph::ObjectId o) const;

  /// Whether object `o` may change what the arrival view of `platform` in `s` shows of the
  /// platform's objects: it is one of them, or it may stand in front of them (conservative).
  bool in_view(const episode::WorldState& s, graph::PlatformId platform, graph::ObjectId o) const;
  /// What the arrival view of `platform` in `s` depends on, as bytes: two states with the same
  /// key see the same (the items in view where they stand, the platform's side).
  std::string view_key(const episode::WorldState& s, graph::PlatformId platform) const;

  /// Draws the scenery of every navigable platform's arrival view on up to `jobs` threads (it is
  /// otherwise drawn on first use, one platform at a time).
  void prepare(int jobs) const;

  const VisibilityOptions& options() const { return options_; }
  /// Distinct views drawn so far (telemetry).
  std::size_t views_drawn() const { return picture_sights_.size(); }

 private:
  struct PictureScenery;  // one picture's camera and its drawing of everything that never moves
  struct Scenery;         // the pictures of a platform's view from one side
  const Scenery& scenery(graph::PlatformId platform, int side) const;
  std::unique_ptr<Scenery> make_scenery(graph::PlatformId platform, int side) const;
  // What decides what a picture shows of the platform's objects in `s`: those objects and the
  // items that may stand in front of them (in id order), where they stand (the memo key), and
  // the pixels they may cover.
  struct Deciders;
  Deciders deciders(const episode::WorldState& s, graph::PlatformId platform, const PictureScenery& sc) const;
  // The numbered items of the view whose marks have a readable place (by object index), laid out
  // on `pass`, a whole pass of the view.
  std::vector<std::int32_t> readable_marks(const episode::WorldState& s, const std::vector<ItemMark>& items,
                                           const Camera& image_camera, const IdImage& pass) const;
  // A drawn window and its silhouettes, kept a short while: a view's visibility and its marks
  // are asked for one right after the other.
  struct Window {
    IdImage image;
    std::vector<ObjectSight> silhouettes;
  };
  std::shared_ptr<const Window> window(const PictureScenery& sc, const Deciders& d) const;
  // The window pasted into a whole pass of the picture (the marks' layouts read whole passes).
  IdImage whole_pass(const PictureScenery& sc, const Deciders& d) const;
  // A picture's counts (memo of its deciders).
  std::shared_ptr<const std::vector<ObjectSight>> picture_counts(const PictureScenery& sc, const Deciders& d) const;
  // Which numbered objects have their place in the marked picture itself, and which are left
  // to its zooms (object indices, sorted).
  struct MarksInPicture {
    std::vector<std::int32_t> placed;
    std::vector<std::int32_t> crowded;
  };
  // The window of the view where the platform's objects can show, drawn with the deciders;
  // their silhouettes go to `silhouettes` (sorted by object index).
  IdImage draw_window(const PictureScenery& sc, const Deciders& d,
                      std::vector<ObjectSight>& silhouettes) const;
  // Item o's pixels in a picture where it stands at `at` (a memo: most of a new state's items
  // stand where they stood in the states drawn before it).
  std::shared_ptr<const Splat> splat(const PictureScenery& sc, graph::ObjectId o, const Eigen::Vector3d& at) const;
  // Object o's world box in `s` (it moves without turning), and where it lands in the view.
  Eigen::AlignedBox3d box_in(const episode::WorldState& s, graph::ObjectId o) const;
  NdcBox image_box(const episode::WorldState& s, graph::ObjectId o, const PictureScenery& sc) const;

  const graph::SceneGraph& g_;
  const SceneGeometry& geometry_;
  VisibilityOptions options_;
  std::vector<graph::ObjectId> movable_;  // the items (they are drawn per state)
  std::vector<Eigen::AlignedBox3d> boxes_;  // each object's world box as the graph found it
  struct SceneryOnce {
    std::once_flag flag;
    std::unique_ptr<Scenery> scenery;
  };
  mutable std::vector<SceneryOnce> scenery_;  // per platform and side, drawn on first use
  // One picture's counts, by its own deciders: a change in one part of a long platform leaves
  // the other parts' pictures as they were.
  mutable BoundedMemoTable<std::shared_ptr<const std::vector<ObjectSight>>> picture_sights_{65536};
  mutable BoundedMemoTable<std::shared_ptr<const Window>> windows_{64};
  mutable BoundedMemoTable<std::shared_ptr<const Splat>> splats_{512};
  mutable BoundedMemoTable<std::shared_ptr<const MarksInPicture>> in_picture_{4096};
  mutable BoundedMemoTable<std::shared_ptr<const std::vector<std::int32_t>>> with_zooms_{1024};
};

/// An id pass with what it counted.
struct IdView {
  IdImage image;
  std::vector<ObjectSight> objects;  // by object index: every object with a silhouette
};

/// The id pass of `camera` in state `s`: every object drawn where `s` puts it, but the held one
/// and `hidden`; `only`, when valid, is the one object drawn.
IdView draw_id_view(const graph::SceneGraph& g, const SceneGeometry& geometry, const episode::WorldState& s,
                    const Camera& camera, const std::vector<graph::ObjectId>& hidden = {},
                    graph::ObjectId only = {});

/// The id pass of `camera` in `s` for what `targets` show: the targets, and whatever may cover
/// part of them in the picture (the held one and `hidden` not); nothing else is drawn, so each
/// target's pixels are those of draw_id_view while other pixels may differ.
IdView draw_id_view_of(const graph::SceneGraph& g, const SceneGeometry& geometry, const episode::WorldState& s,
                       const Camera& camera, const std::vector<graph::ObjectId>& targets,
                       const std::vector<graph::ObjectId>& hidden = {});

/// Fills in each entry's visible pixels from `image`; `silhouettes` are sorted by object index.
std::vector<ObjectSight> count_pixels(const IdImage& image, std::vector<ObjectSight> silhouettes);

/// The objects with some pixels in a picture's counts (which items a part's picture numbers).
std::vector<graph::ObjectId> showing_in(const std::vector<ObjectSight>& sights);

}  // namespace mtg::render
