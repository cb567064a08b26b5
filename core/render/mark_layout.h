#pragma once
// Where each item's number goes in a marked image, so that a person can tell which number is
// which (docs/render.md, "Marks a person can read"). From the id pass of the view:
//   - the anchor dot sits on the object's visible pixels, at the one deepest inside them;
//   - a disc sits on its own object when that object holds most of it (no leader line), else
//     beside it, joined to the dot by a leader line;
//   - no disc covers another mark's dot, or more than kMaxCover of the visible pixels of any other
//     object that is numbered; discs do not overlap; leader lines do not cross each other, pass
//     over another dot, or run through another disc; every disc is inside the image.
// A mark that finds no such place is left to a zoomed view of its part of the picture
// (zoom_cameras), where the same rules hold at a larger scale. Deterministic: fixed candidate
// positions tried in a fixed order, marks placed in number order.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/episode/world_state.h"
#include "core/render/camera.h"
#include "core/render/id_raster.h"
#include "core/render/marks.h"
#include "core/render/scene_geometry.h"

namespace mtg::render {

/// The share of another numbered object's visible pixels a disc may cover, at most.
inline constexpr double kMaxCover = 0.10;
/// A numbered object showing fewer pixels than this share of the image (1,600 at 640x480, about
/// 40 x 40) is also shown in a zoomed view, larger, whether or not its mark found a place.
inline constexpr double kSmallShare = 1600.0 / (640.0 * 480.0);

/// Sizes of the marks drawn on a `width` x `height` image.
struct MarkStyle {
  int radius = 13;      // number disc
  int dot_radius = 4;   // anchor dot
  double font = 0.5;    // cv::putText scale
  int thickness = 2;
};
MarkStyle mark_style(int width, int height);

struct PlacedMark {
  int number = 0;
  graph::ObjectId object;
  Eigen::Vector2d anchor = Eigen::Vector2d::Zero();  // image pixels: the dot
  Eigen::Vector2d disc = Eigen::Vector2d::Zero();    // image pixels: the disc's centre
  bool visible = false;  // the object shows in the view: the dot is on its pixels
  bool on_object() const { return (anchor - disc).norm() < 0.5; }
};

struct MarkLayout {
  MarkStyle style;
  std::vector<PlacedMark> placed;
  std::vector<ItemMark> crowded;  // no readable place here: for a zoomed view
  std::vector<ItemMark> small;    // placed, but small in the picture: shown larger in a zoomed view too
};

/// The layout of `items` on an image of `camera` whose id pass is `ids` (the same view at
/// 1/`scale` of the image's size). Items whose object shows nowhere in the pass are placed at
/// their projected anchor when that is in the image (never named by tasks, still numbered).
MarkLayout layout_item_marks(const IdImage& ids, int scale, const Camera& camera, const std::vector<ItemMark>& items);

/// The rules above, checked on a finished layout against the id pass: one line per broken rule
/// (empty when it is readable). Tests and `mtg render --marks` use it.
std::vector<std::string> check_layout(const MarkLayout& layout, const IdImage& ids, int scale, int width, int height);

/// A zoomed view of part of a picture: the camera, what it is for, and where it is in the
/// picture (image pixels), for a frame drawn there.
struct ZoomView {
  Camera camera;
  std::vector<ItemMark> items;  // what it numbers: the crowded marks, and every other in its region
  Eigen::AlignedBox2d region;   // in the first picture's pixels
};

/// A zoomed view with its marks laid out, and the regions of its own zooms (framed on it).
struct MarkedZoom {
  ZoomView view;
  MarkLayout layout;
  std::vector<Eigen::AlignedBox2d> regions;
  std::vector<std::size_t> region_zooms;  // each region's zoom: its index in ItemMarksPlan::zooms
  IdImage pass;  // the id pass its marks were laid out on
};

/// Every item mark of a picture placed: in the picture itself, or in a zoomed view of its
/// crowded part (and, where that is still crowded, a zoom of the zoom; two levels at most).
/// Zooms are in the order their images follow the picture (depth first).
struct ItemMarksPlan {
  Camera camera;  // the picture's
  std::vector<ItemMark> items;
  IdImage pass;   // the id pass the picture's marks were laid out on
  MarkLayout layout;
  std::vector<Eigen::AlignedBox2d> regions;  // the picture's zooms, framed on it
  std::vector<std::size_t> region_zooms;     // each region's zoom: its index in `zooms`
  std::vector<MarkedZoom> zooms;
  /// Whether item number `n` has a readable place in the picture or a zoom.
  bool placed(int number) const;
  /// Every broken rule of every layout, checked on the id passes they were laid out on,
  /// "<picture>: <problem>" (mtg render --marks-json, tests).
  std::vector<std::string> problems() const;
};

/// The id pass marks are laid out on is this many times smaller than the image each way.
inline constexpr int kMarkPassScale = 2;

/// Lays out `items` on the picture `camera` takes of state `s` (the held item and `hidden` not
/// drawn), with the zooms the crowded ones need. Pure: the id passes come from `geometry`.
ItemMarksPlan plan_item_marks(const graph::SceneGraph& g, const SceneGeometry& geometry, const episode::WorldState& s,
                              const Camera& camera, const std::vector<ItemMark>& items,
                              const std::vector<graph::ObjectId>& hidden = {});
/// The same, given the picture's id pass (mark_pass, or a pass whose numbered objects' pixels are
/// the same); the zooms' passes are drawn here.
ItemMarksPlan plan_item_marks(const graph::SceneGraph& g, const SceneGeometry& geometry, const episode::WorldState& s,
                              const Camera& camera, const std::vector<ItemMark>& items,
                              const std::vector<graph::ObjectId>& hidden, const IdImage& pass);

/// The name of zoomed view `k` (0-based) of a picture: "Z1", "Z2", ...
std::string zoom_name(std::size_t k);

/// The id pass the marks of `items` in `camera`'s picture are laid out on: the items' pixels as a
/// whole pass has them (draw_id_view_of; only what may cover an item is drawn besides).
IdImage mark_pass(const graph::SceneGraph& g, const SceneGeometry& geometry, const episode::WorldState& s,
                  const Camera& camera, const std::vector<ItemMark>& items,
                  const std::vector<graph::ObjectId>& hidden = {});

/// A mark's place in a picture, for clustering them into zoomed views.
struct ZoomPoint {
  int number = 0;
  Eigen::Vector2d at = Eigen::Vector2d::Zero();
};

/// A zoomed view of a cluster of points: the same eye looking through the cluster's middle.
struct ZoomFrame {
  Camera camera;
  Eigen::AlignedBox2d region;  // in the picture's pixels
  std::vector<int> numbers;    // the points it was made for
};

/// Zoomed views for `points` of a picture of `camera` (marks of disc radius `radius`): clusters
/// of points within a quarter of the image's width, each at most a third of it wide, merged
/// neighbour by neighbour down to `max_views`; each view's lens narrowed so its cluster, with a
/// margin, fills the image, at least twice as big as in the picture. None for an orthographic
/// camera.
std::vector<ZoomFrame> zoom_frames(const Camera& camera, std::vector<ZoomPoint> points, double radius, int max_views);

/// Cameras for the crowded marks of a layout of `items` (and, `with_small`, its small ones): the
/// same eye, aimed at each cluster of them (anchors within a quarter of the image's width of each
/// other) and narrowed so the cluster, with a margin, fills the image; at most `max_views`. Each
/// numbers every item whose anchor lies in its region, so no look-alike there goes unnumbered.
std::vector<ZoomView> zoom_views(const Camera& camera, const MarkLayout& layout, const std::vector<ItemMark>& items,
                                 bool with_small, int max_views = 3);

}  // namespace mtg::render
