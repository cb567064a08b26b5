#include "core/render/image_renderer.h"

#include "core/episode/state_delta.h"
#include "core/render/image_codec.h"
#include "core/render/view.h"
#include "core/util/error.h"
#include "core/util/log.h"
#include "core/util/parallel.h"

namespace mtg::render {
namespace {

const char* role_of(ViewKind kind) {
  switch (kind) {
    case ViewKind::kPlatform: return "view";
    case ViewKind::kItem: return "item";
    case ViewKind::kFocus: return "focus";
    case ViewKind::kTopdown: return "topdown";
  }
  return "view";
}

}  // namespace

ImageRenderer::ImageRenderer(std::string profile, RendererOptions options)
    : scenes_(std::move(profile), /*with_textures=*/true), options_(options) {
  log::info("renderer: " + context_.description());
}

SceneRenderer& ImageRenderer::scene_renderer(const graph::SceneCache::Entry& entry) {
  auto& slot = renderers_[entry.key];
  if (!slot) slot = std::make_unique<SceneRenderer>(context_, entry.scene, entry.graph, options_);
  return *slot;
}

ImageReply ImageRenderer::render(const ImageRequest& request) {
  // Everything that can be checked without the scene first, so a bad request costs nothing.
  require_image_size(request.width, request.height);
  require_encoding(request.encoding);
  if (request.views.empty()) throw Error("render: the request asks for no views");

  const graph::SceneCache::Entry& entry = scenes_.load(request.scene, request.data_dir);
  const graph::SceneGraph& g = entry.graph;
  const episode::WorldState state = episode::apply_delta(g, request.state);
  SceneRenderer& renderer = scene_renderer(entry);

  // Every view is drawn first (the GL context is this thread's), then all images are encoded at
  // once: encoding is most of an observation's time, and each image is encoded on its own.
  ImageReply reply;
  std::vector<ViewImages> drawn;
  std::vector<std::string> roles;  // one per image, in reply order
  for (const ViewSpec& v : request.views) {
    ViewRequest r;
    r.view = v.view;
    r.marks = v.marks;
    r.width = request.width;
    r.height = request.height;
    r.side = v.side;
    r.min_region_size = request.min_region_size;
    if (r.view == ViewKind::kPlatform) {
      r.platform = g.find_platform(v.platform);
      if (!r.platform.valid()) throw Error("render: scene " + request.scene + " has no platform '" + v.platform + "'");
    }
    if (r.view == ViewKind::kItem || r.view == ViewKind::kFocus) {
      r.object = g.find_object(v.item);
      if (!r.object.valid()) throw Error("render: scene " + request.scene + " has no object '" + v.item + "'");
    }
    const ViewPlan plan = plan_view(g, state, r);
    drawn.push_back(draw_view(renderer, g, state, plan, v.marks != MarkKind::kNone));
    reply.triangles += drawn.back().triangles;
    roles.push_back(role_of(r.view));
    if (!drawn.back().marked.empty()) roles.push_back(roles.back() + "_marked");
  }
  const std::vector<const cv::Mat*> images = images_in_reply_order(drawn);
  std::vector<std::vector<std::uint8_t>> bytes =
      encode_images(images, request.encoding, jobs_or_cores(options_.encode_jobs));
  const std::string encoding = request.encoding == "jpg" ? "jpeg" : request.encoding;
  for (std::size_t i = 0; i < images.size(); ++i) {
    EncodedImage e;
    e.role = roles[i];
    e.encoding = encoding;
    e.width = images[i]->cols;
    e.height = images[i]->rows;
    e.bytes = std::move(bytes[i]);
    reply.images.push_back(std::move(e));
  }
  return reply;
}

}  // namespace mtg::render
