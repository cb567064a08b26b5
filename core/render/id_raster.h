#pragma once
// An object-id pass on the CPU: which graph object each pixel of a camera view shows, with a
// depth test, no face culling (as the GL renderer draws) and the near plane clipped. It is the
// GL renderer's view drawn with one flat colour per object, computed in plain float arithmetic
// in a fixed order, so its pixels do not depend on the machine or its GPU: task generation
// decides what is visible from it, and the renderer places its marks on it (docs/render.md,
// "What the agent can see").

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "core/render/camera.h"
#include "core/render/scene_geometry.h"

namespace mtg::render {

/// Pixels of an id pass, or of a window of one: row-major; pixel (u, v) of the window is pixel
/// (left + u, top + v) of the camera's image, (0, 0) its top-left corner as in Camera::project.
struct IdImage {
  static constexpr std::int32_t kNone = -1;

  int left = 0;  // where the window starts in the camera's image
  int top = 0;
  int width = 0;
  int height = 0;
  std::vector<std::int32_t> ids;  // graph object index, or kNone (background)
  std::vector<float> depth;       // normalised device depth of what the pixel shows

  IdImage() = default;
  IdImage(int w, int h) : IdImage(0, 0, w, h) {}
  IdImage(int left, int top, int w, int h);
  /// The pixel at (u, v) of the window.
  std::int32_t at(int u, int v) const { return ids[static_cast<std::size_t>(v) * static_cast<std::size_t>(width) + u]; }
  /// The window `left, top, w, h` of this one (which must hold it).
  IdImage window(int left, int top, int w, int h) const;
  /// A window `left, top, w, h` with no pixels yet, its storage reserved: for append_window.
  static IdImage unfilled(int left, int top, int w, int h);
};

/// Appends the pixels (l, t, w, h) of a row-major image window at (left, top), `width` wide, to
/// `out` (converted to its type): the window of an id image, or of one kept in fewer bits.
template <class From, class To>
void append_window(const std::vector<From>& from, int left, int top, int width, int l, int t, int w, int h,
                   std::vector<To>& out) {
  for (int v = 0; v < h; ++v) {
    const auto begin = static_cast<std::ptrdiff_t>(static_cast<std::size_t>(t - top + v) * static_cast<std::size_t>(width) +
                                                   static_cast<std::size_t>(l - left));
    out.insert(out.end(), from.begin() + begin, from.begin() + begin + w);
  }
}

/// The same view as `camera` at another resolution (same lens, same aspect when the sizes are
/// in proportion).
Camera at_resolution(const Camera& camera, int width, int height);

/// Whether anything inside the world box `box_W` can show in the view (conservative: a box
/// wholly outside one side of the frustum, or behind the near plane, cannot).
bool may_show(const Eigen::Matrix4f& clip_from_world, const Eigen::AlignedBox3d& box_W);

/// One object's pixels in a camera's image, drawn alone: each pixel it covers once, with the
/// nearest depth it has there. Drawing it onto a pass of that camera (composite) gives the pixels
/// and the silhouette IdPass::draw gives for the object's triangles at that pose, so an object
/// that stands where it stood need not be drawn again (visibility.cc keeps them per picture).
struct Splat {
  /// Pixels (u, v) ... (u + length - 1, v) of the camera's image, by v then u.
  struct Run {
    std::int32_t v = 0;
    std::int32_t u = 0;
    std::int32_t length = 0;
  };
  std::vector<Run> runs;
  std::vector<float> depth;  // per pixel of the runs in turn; +infinity where no depth passed
};

/// The splat of `triangles` placed by `X_WO` in `camera`'s image.
Splat splat_of(const Camera& camera, const ObjectTriangles& triangles, const Eigen::Isometry3d& X_WO);

/// Draws `splat` onto `image`, a window of its camera's image, as object `id`, nearest surface
/// first; returns the window's pixels it covers.
int composite(const Splat& splat, std::int32_t id, IdImage& image);

/// Draws objects into an id image, nearest surface first.
class IdPass {
 public:
  /// An empty image (every pixel kNone) of the camera's size.
  explicit IdPass(const Camera& camera);
  /// Starts from `background`: an earlier pass of the same camera, or a window of one (then only
  /// that window is drawn, and silhouettes count its pixels only).
  IdPass(const Camera& camera, IdImage background);

  /// Draws `triangles` placed by `X_WO` as object `id`; returns the pixels the object covers on
  /// its own (its silhouette, each pixel once, whatever else is drawn).
  int draw(const ObjectTriangles& triangles, const Eigen::Isometry3d& X_WO, std::int32_t id);

  /// Whether the last draw covered pixel `i` of the image (row-major in its window).
  bool covered_by_last_draw(std::size_t i) const { return stamp_[i] == draw_count_; }

  const IdImage& image() const { return image_; }
  IdImage take() { return std::move(image_); }
  const Eigen::Matrix4f& clip_from_world() const { return clip_from_world_; }

 private:
  void fill_triangle(const Eigen::Vector4f& a, const Eigen::Vector4f& b, const Eigen::Vector4f& c, std::int32_t id,
                     int& covered);

  Eigen::Matrix4f clip_from_world_;
  int full_width_ = 0;  // the camera's image; image_ may be a window of it
  int full_height_ = 0;
  IdImage image_;
  std::vector<std::uint32_t> stamp_;  // which draw last covered each pixel (silhouettes)
  std::uint32_t draw_count_ = 0;
  std::vector<Eigen::Vector4f> clip_;  // scratch: one object's vertices in clip space
};

}  // namespace mtg::render
