#include "services/renderer/renderer.h"

#include "core/episode/state_json.h"
#include "core/render/image_codec.h"
#include "core/render/view.h"
#include "core/util/error.h"
#include "core/util/log.h"

namespace mtg::services {
namespace {

const char* role_of(render::ViewKind kind) {
  switch (kind) {
    case render::ViewKind::kPlatform: return "view";
    case render::ViewKind::kItem: return "item";
    case render::ViewKind::kFocus: return "focus";
    case render::ViewKind::kTopdown: return "topdown";
  }
  return "view";
}

EncodedImage encode(const cv::Mat& image, const std::string& role, const std::string& encoding) {
  EncodedImage out;
  out.role = role;
  out.encoding = encoding == "jpg" ? "jpeg" : encoding;
  out.width = image.cols;
  out.height = image.rows;
  out.bytes = render::encode_image(image, encoding);
  return out;
}

}  // namespace

Renderer::Renderer(std::string profile, render::RendererOptions options)
    : scenes_(std::move(profile), /*with_textures=*/true), options_(options) {
  log::info("renderer: " + context_.description());
}

render::SceneRenderer& Renderer::scene_renderer(const SceneCache::Entry& entry) {
  auto& slot = renderers_[entry.key];
  if (!slot) slot = std::make_unique<render::SceneRenderer>(context_, entry.scene, entry.graph, options_);
  return *slot;
}

ImageReply Renderer::render(const ImageRequest& request) {
  // Everything that can be checked without the scene first, so a bad request costs nothing.
  render::require_image_size(request.width, request.height);
  render::require_encoding(request.encoding);
  if (request.views.empty()) throw Error("render: the request asks for no views");
  std::vector<std::pair<render::ViewKind, render::MarkKind>> kinds;
  for (const ViewSpec& v : request.views) kinds.emplace_back(render::parse_view_kind(v.view), render::parse_mark_kind(v.marks));

  const SceneCache::Entry& entry = scenes_.load(request.scene, request.data_dir);
  const graph::SceneGraph& g = entry.graph;
  nlohmann::json delta;
  if (!request.state_json.empty()) {
    delta = nlohmann::json::parse(request.state_json, nullptr, /*allow_exceptions=*/false);
    if (delta.is_discarded()) throw Error("render: state_json is not valid JSON");
  }
  const episode::WorldState state = episode::state_from_delta_json(g, delta);
  render::SceneRenderer& renderer = scene_renderer(entry);

  ImageReply reply;
  for (std::size_t k = 0; k < request.views.size(); ++k) {
    const ViewSpec& v = request.views[k];
    render::ViewRequest r;
    r.view = kinds[k].first;
    r.marks = kinds[k].second;
    r.width = request.width;
    r.height = request.height;
    r.side = v.side;
    r.min_region_size = request.min_region_size;
    if (r.view == render::ViewKind::kPlatform) {
      r.platform = g.find_platform(v.platform);
      if (r.platform < 0) throw Error("render: scene " + request.scene + " has no platform '" + v.platform + "'");
    }
    if (r.view == render::ViewKind::kItem || r.view == render::ViewKind::kFocus) {
      r.object = g.find_object(v.item);
      if (r.object < 0) throw Error("render: scene " + request.scene + " has no object '" + v.item + "'");
    }
    const render::ViewPlan plan = render::plan_view(g, state, r);
    const render::ViewImages images = render::draw_view(renderer, g, state, plan, !v.marks.empty());
    reply.triangles += images.triangles;
    const std::string role = role_of(r.view);
    reply.images.push_back(encode(images.plain, role, request.encoding));
    if (!images.marked.empty()) reply.images.push_back(encode(images.marked, role + "_marked", request.encoding));
  }
  return reply;
}

}  // namespace mtg::services
