#pragma once
// The renderer's work without the bus: load a scene once (meshes, textures, graph), then turn a
// request for some views of a world state into encoded images. The renderer process and
// `mtg render` both use it; it holds the process's one GL context.

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/render/gl/gl_context.h"
#include "core/render/gl/scene_renderer.h"
#include "services/common/scene_cache.h"

namespace mtg::services {

struct ViewSpec {
  std::string view = "platform";  // platform, item, topdown
  std::string platform;
  int side = -1;
  std::string item;
  std::string marks;  // items, targets, labels, "" (no marked copy)
};

struct ImageRequest {
  std::string scene;
  std::string data_dir;
  int width = 640;
  int height = 480;
  std::string encoding = "png";
  std::string state_json;        // "" = the scene as the graph found it
  double min_region_size = 0.03;
  std::vector<ViewSpec> views;
};

struct EncodedImage {
  std::string role;  // view, view_marked, item, topdown, topdown_marked
  std::string encoding;
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> bytes;
};

struct ImageReply {
  std::vector<EncodedImage> images;
  std::int64_t triangles = 0;
};

class Renderer {
 public:
  /// @throws mtg::Error when no headless GL context can be made.
  explicit Renderer(std::string profile = "replica_cad", render::RendererOptions options = {});

  /// @throws mtg::Error with a one-line message naming the bad field, name or file.
  ImageReply render(const ImageRequest& request);

  const std::string& gl_description() const { return context_.description(); }
  /// The loaded scene and its GPU copy (loading them on first use).
  render::SceneRenderer& scene_renderer(const SceneCache::Entry& entry);
  SceneCache& scenes() { return scenes_; }

 private:
  SceneCache scenes_;
  render::RendererOptions options_;
  render::GlContext context_;
  std::map<std::string, std::unique_ptr<render::SceneRenderer>> renderers_;
};

}  // namespace mtg::services
