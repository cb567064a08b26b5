#include "core/render/image_renderer.h"

#include "core/episode/state_delta.h"
#include "core/render/image_codec.h"
#include "core/render/view.h"
#include "core/util/error.h"
#include "core/util/log.h"

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

EncodedImage encode(const cv::Mat& image, const std::string& role, const std::string& encoding) {
  EncodedImage out;
  out.role = role;
  out.encoding = encoding == "jpg" ? "jpeg" : encoding;
  out.width = image.cols;
  out.height = image.rows;
  out.bytes = encode_image(image, encoding);
  return out;
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

  ImageReply reply;
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
    const ViewImages images = draw_view(renderer, g, state, plan, v.marks != MarkKind::kNone);
    reply.triangles += images.triangles;
    const std::string role = role_of(r.view);
    reply.images.push_back(encode(images.plain, role, request.encoding));
    if (!images.marked.empty()) reply.images.push_back(encode(images.marked, role + "_marked", request.encoding));
  }
  return reply;
}

}  // namespace mtg::render
