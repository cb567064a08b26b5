#pragma once
// A scene's meshes and textures on the GPU (uploaded once) and the draw of one camera view into
// an offscreen framebuffer, read back as an 8-bit BGR image. Objects are drawn where a world
// state puts them; doors and drawers (movable URDF links) are left out, as the scene graph
// leaves them out, so shelves and cavities the agent is sent to are visible.

#include <cstdint>
#include <map>
#include <memory>
#include <opencv2/core.hpp>
#include <vector>

#include "core/graph/scene_graph.h"
#include "core/render/camera.h"
#include "core/episode/world_state.h"
#include "core/render/gl/gl_context.h"
#include "core/render/scene_geometry.h"
#include "core/scene/scene.h"
#include "core/util/id_vector.h"

namespace mtg::render {

struct RendererOptions {
  int max_texture_size = 512;  // textures are downsampled to this edge on upload (memory, speed)
  int encode_jobs = 0;         // threads encoding one reply's images (ImageRenderer); 0: one per core
  cv::Scalar background{235, 222, 214};  // BGR: a light neutral, distinct from white surfaces
};

struct Frame {
  cv::Mat image;             // BGR, camera.height x camera.width
  std::int64_t triangles = 0;
};

struct ViewPlan;

class SceneRenderer {
 public:
  /// Uploads every mesh of `scene`; graph objects are matched to scene objects by name.
  /// Needs a current GlContext. @throws mtg::Error when a texture cannot be decoded or GL fails.
  SceneRenderer(const GlContext& context, const scene::Scene& scene, const graph::SceneGraph& graph,
                RendererOptions options = {});
  ~SceneRenderer();
  SceneRenderer(const SceneRenderer&) = delete;
  SceneRenderer& operator=(const SceneRenderer&) = delete;

  /// Draws graph objects at `poses_W` (one per graph object) except those with draw[i] false.
  Frame render(const Camera& camera, const IdVector<graph::ObjectId, Eigen::Isometry3d>& poses_W,
               const IdVector<graph::ObjectId, bool>& draw);

  /// Whether graph object `o` has any geometry to draw (its meshes may be missing from the data).
  bool has_geometry(graph::ObjectId o) const;
  std::int64_t uploaded_texture_bytes() const { return texture_bytes_; }

 private:
  struct GpuMesh;
  struct DrawPart {
    const GpuMesh* mesh = nullptr;
    Eigen::Affine3d T_OA = Eigen::Affine3d::Identity();  // mesh coordinates -> object frame
  };
  void ensure_framebuffer(int width, int height);
  const GpuMesh* upload(const scene::MeshHandle& mesh);

  RendererOptions options_;
  std::map<const scene::Mesh*, std::unique_ptr<GpuMesh>> meshes_;
  IdVector<graph::ObjectId, std::vector<DrawPart>> parts_;
  unsigned program_ = 0;
  unsigned framebuffer_ = 0, colour_ = 0, depth_ = 0;
  int fb_width_ = 0, fb_height_ = 0;
  std::int64_t texture_bytes_ = 0;
};

/// A zoomed view of a crowded part of a marked picture (mark_layout.h), marked.
struct ZoomImage {
  cv::Mat marked;
  std::vector<int> numbers;  // the item (or placement target) numbers it shows
  bool targets = false;      // it numbers placement targets, not items
};

/// The plain image of a planned view and, when `with_marks`, the marked copy (drawn even when
/// there is nothing to mark, so replies always have the same images) with the zoomed views its
/// crowded item marks need.
struct ViewImages {
  cv::Mat plain;
  cv::Mat marked;  // empty when not asked for
  std::vector<ZoomImage> zooms;
  std::vector<int> zoomed;  // the item numbers the marked copy leaves to its zooms
  std::vector<int> zoomed_targets;  // the placement targets it leaves to its zooms
  std::int64_t triangles = 0;
};

/// Draws `plan` in world state `s`. Item marks are laid out on the id pass of the view drawn
/// from `geometry` (the same triangles). @throws mtg::Error when the plan's single object (an
/// item close-up) has no geometry, naming the object.
ViewImages draw_view(SceneRenderer& renderer, const graph::SceneGraph& g, const episode::WorldState& s,
                     const ViewPlan& plan, bool with_marks, const SceneGeometry& geometry);

/// The images of several views in the order a reply carries them: each view's plain image, then
/// its marked copy when it has one, then its zooms. The pointers are into `views`.
std::vector<const cv::Mat*> images_in_reply_order(const std::vector<ViewImages>& views);

}  // namespace mtg::render
