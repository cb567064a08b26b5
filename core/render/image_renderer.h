#pragma once
// Images of a scene on request: load a scene once (meshes, textures, graph), then turn a request
// for some views of a world state into encoded images. The renderer process and `mtg render` both
// use it; it holds the process's one GL context.

#include <map>
#include <memory>
#include <cstdint>
#include <string>
#include <vector>

#include "core/graph/scene_cache.h"
#include "core/render/gl/gl_context.h"
#include "core/render/gl/scene_renderer.h"
#include "core/render/image_request.h"

namespace mtg::render {

/// A request drawn and not yet encoded: its frames, and the words for each image in the order
/// the reply carries them. Encoding needs no GL, so another thread may do it (the renderer
/// process draws the next request meanwhile).
struct DrawnReply {
  std::vector<ViewImages> views;
  std::vector<std::string> roles;     // one per image, in reply order
  std::vector<std::string> captions;  // likewise
  std::string encoding;               // as asked: png, jpeg or jpg
  std::int64_t triangles = 0;
  /// The frames in reply order (pointers into `views`).
  std::vector<const cv::Mat*> images() const { return images_in_reply_order(views); }
};

/// The reply of `drawn` with `bytes[i]` the encoding of its image i.
ImageReply encoded_reply(const DrawnReply& drawn, std::vector<std::vector<std::uint8_t>> bytes);

class ImageRenderer {
 public:
  /// On `gpu` (the hardware EGL device of that index, modulo how many there are; -1 = the
  /// first). @throws mtg::Error when no headless GL context can be made.
  /// `rules`: as the tasks drawn were planned (tasks::platform_rules_of_format).
  explicit ImageRenderer(std::string profile = "replica_cad", RendererOptions options = {}, int gpu = -1,
                         graph::PlatformRules rules = graph::PlatformRules::kReachedAndSeen);

  /// draw() then every image encoded, on up to RendererOptions::encode_jobs threads.
  /// @throws mtg::Error with a one-line message naming the bad field, name or file.
  ImageReply render(const ImageRequest& request);
  /// Every view of the request drawn on this thread's GL context, nothing encoded.
  /// @throws mtg::Error as render().
  DrawnReply draw(const ImageRequest& request);

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
