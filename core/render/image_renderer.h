#pragma once
// Images of a scene on request: load a scene once (meshes, textures, graph), then turn a request
// for some views of a world state into encoded images. The renderer process and `mtg render` both
// use it; it holds the process's one GL context.

#include <map>
#include <memory>
#include <string>

#include "core/graph/scene_cache.h"
#include "core/render/gl/gl_context.h"
#include "core/render/gl/scene_renderer.h"
#include "core/render/image_request.h"

namespace mtg::render {

class ImageRenderer {
 public:
  /// @throws mtg::Error when no headless GL context can be made.
  explicit ImageRenderer(std::string profile = "replica_cad", RendererOptions options = {});

  /// @throws mtg::Error with a one-line message naming the bad field, name or file.
  ImageReply render(const ImageRequest& request);

  const std::string& gl_description() const { return context_.description(); }
  /// The loaded scene and its GPU copy (loading them on first use).
  SceneRenderer& scene_renderer(const graph::SceneCache::Entry& entry);
  /// The scene's triangles for the CPU id passes (marks), made on first use.
  const SceneGeometry& geometry(const graph::SceneCache::Entry& entry);
  graph::SceneCache& scenes() { return scenes_; }

 private:
  graph::SceneCache scenes_;
  RendererOptions options_;
  GlContext context_;
  std::map<std::string, std::unique_ptr<SceneRenderer>> renderers_;
  std::map<std::string, std::unique_ptr<SceneGeometry>> geometries_;
};

}  // namespace mtg::render
