#include "core/render/image_renderer.h"

#include <algorithm>
#include <cctype>

#include "core/episode/state_delta.h"
#include "core/render/image_codec.h"
#include "core/render/mark_layout.h"
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

std::string numbers_text(const std::vector<int>& numbers) {
  std::string out;
  for (std::size_t i = 0; i < numbers.size(); ++i) {
    out += (i == 0 ? "" : i + 1 == numbers.size() ? " and " : ", ") + std::to_string(numbers[i]);
  }
  return out;
}

std::string join_words(const std::string& a, const std::string& b) {
  return a.empty() ? b : b.empty() ? a : a + " " + b;
}

// What a marked view leaves to its zoomed views, in words.
std::string zoomed_caption(const ViewImages& images, std::size_t first) {
  if (images.zooms.empty()) return "";
  const std::size_t n = images.zooms.size();
  std::string out = n == 1   ? "The close-up " + zoom_name(first) + " (framed here) shows"
                    : n == 2 ? "The close-ups " + zoom_name(first) + " and " + zoom_name(first + 1) + " (framed here) show"
                             : "The close-ups " + zoom_name(first) + " to " + zoom_name(first + n - 1) + " (framed here) show";
  out += images.zoomed_targets.empty() ? " small or crowded objects larger." : " crowded free spaces larger.";
  std::vector<int> numbers = images.zoomed;
  std::sort(numbers.begin(), numbers.end());
  if (!numbers.empty()) {
    out += numbers.size() == 1 ? " Object " + numbers_text(numbers) + " is numbered only there."
                               : " Objects " + numbers_text(numbers) + " are numbered only there.";
  }
  std::vector<int> targets = images.zoomed_targets;
  std::sort(targets.begin(), targets.end());
  if (!targets.empty()) {
    out += targets.size() == 1 ? " Free space " + numbers_text(targets) + " is numbered only there."
                               : " Free spaces " + numbers_text(targets) + " are numbered only there.";
  }
  return out;
}

std::string zoom_caption(std::size_t k, const ZoomImage& z) {
  std::vector<int> numbers = z.numbers;
  std::sort(numbers.begin(), numbers.end());
  // One number reads as one ("object 2 numbered as its key"; a rater read "objects 2" twice).
  const bool one = numbers.size() == 1;
  return zoom_name(k) + ": a close-up of the part framed " + zoom_name(k) + " in the marked view, from where you stand; " +
         (z.targets ? (one ? "free space " : "free spaces ") : (one ? "object " : "objects ")) + numbers_text(numbers) +
         (one ? " numbered as its key." : " numbered as their keys.");
}

// The pictures of a platform view after the whole platform's: each part of a long platform, seen
// from in front of it, numbered as the whole (its own part's objects and whatever else shows).
std::vector<ViewPlan> part_plans(const graph::SceneGraph& g, const SceneGeometry& geometry,
                                 const episode::WorldState& s, const ViewRequest& r, const ViewPlan& whole) {
  std::vector<ViewPlan> out;
  const std::vector<PlatformPicture> pictures = platform_pictures(g, s, r.platform, whole.side, r.width, r.height);
  for (std::size_t k = 1; k < pictures.size(); ++k) {
    ViewPlan part = whole;
    part.camera = pictures[k].camera;
    if (!whole.marks.items.empty()) {
      const IdImage pass = mark_pass(g, geometry, s, part.camera, whole.marks.items, whole.hidden);
      std::vector<graph::ObjectId> showing;
      for (const std::int32_t id : pass.ids) {
        if (id < 0) continue;
        const graph::ObjectId o = graph::ObjectId::of_index(static_cast<std::size_t>(id));
        if (std::find(showing.begin(), showing.end(), o) == showing.end()) showing.push_back(o);
      }
      part.marks.items = numbered_in(g, s, r.platform, whole.side, pictures[k], whole.marks.items, showing);
    }
    part.marks.regions = regions_in(g, s, r.platform, whole.side, pictures[k], whole.marks.regions);
    out.push_back(std::move(part));
  }
  return out;
}

std::string part_caption(const PlatformPicture& picture, const std::string& platform) {
  std::string words = part_words(picture);
  words[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(words[0])));
  return words + " of " + platform + ", seen from where you stand, numbered as in the whole view.";
}

}  // namespace

ImageRenderer::ImageRenderer(std::string profile, RendererOptions options, int gpu, graph::PlatformRules rules)
    : scenes_(std::move(profile), rules, /*with_textures=*/true), options_(options), context_(gpu) {
  log::info("renderer: " + context_.description());
}

SceneRenderer& ImageRenderer::scene_renderer(const graph::SceneCache::Entry& entry) {
  auto& slot = renderers_[entry.key];
  if (!slot) slot = std::make_unique<SceneRenderer>(context_, entry.scene, entry.graph, options_);
  return *slot;
}

const SceneGeometry& ImageRenderer::geometry(const graph::SceneCache::Entry& entry) {
  auto& slot = geometries_[entry.key];
  if (!slot) slot = std::make_unique<SceneGeometry>(entry.scene, entry.graph);
  return *slot;
}

ImageReply ImageRenderer::render(const ImageRequest& request) {
  const DrawnReply drawn = draw(request);
  return encoded_reply(drawn, encode_images(drawn.images(), drawn.encoding, jobs_or_cores(options_.encode_jobs)));
}

ImageReply encoded_reply(const DrawnReply& drawn, std::vector<std::vector<std::uint8_t>> bytes) {
  const std::vector<const cv::Mat*> images = drawn.images();
  if (bytes.size() != images.size()) throw Error("render: internal: " + std::to_string(bytes.size()) + " encodings of " +
                                                 std::to_string(images.size()) + " images");
  const std::string encoding = drawn.encoding == "jpg" ? "jpeg" : drawn.encoding;
  ImageReply reply;
  reply.triangles = drawn.triangles;
  for (std::size_t i = 0; i < images.size(); ++i) {
    EncodedImage e;
    e.role = drawn.roles[i];
    e.caption = drawn.captions[i];
    e.encoding = encoding;
    e.width = images[i]->cols;
    e.height = images[i]->rows;
    e.bytes = std::move(bytes[i]);
    reply.images.push_back(std::move(e));
  }
  return reply;
}

DrawnReply ImageRenderer::draw(const ImageRequest& request) {
  // Everything that can be checked without the scene first, so a bad request costs nothing.
  require_image_size(request.width, request.height);
  require_encoding(request.encoding);
  if (request.views.empty()) throw Error("render: the request asks for no views");

  const graph::SceneCache::Entry& entry = scenes_.load(request.scene, request.data_dir);
  const graph::SceneGraph& g = entry.graph;
  const episode::WorldState state = episode::apply_delta(g, request.state);
  SceneRenderer& renderer = scene_renderer(entry);

  // Every view is drawn first (the GL context is this thread's); the images are encoded after,
  // all at once: encoding is most of an observation's time, and each image is encoded on its own.
  DrawnReply out;
  out.encoding = request.encoding;
  std::vector<ViewImages>& drawn = out.views;
  std::vector<std::string>& roles = out.roles;
  std::vector<std::string>& captions = out.captions;
  for (const ViewSpec& v : request.views) {
    ViewRequest r;
    r.view = v.view;
    r.marks = v.marks;
    r.width = request.width;
    r.height = request.height;
    r.side = v.side;
    r.min_region_size = request.min_region_size;
    r.number = v.number;
    if (r.view == ViewKind::kPlatform) {
      r.platform = g.find_platform(v.platform);
      if (!r.platform.valid()) throw Error("render: scene " + request.scene + " has no platform '" + v.platform + "'");
    }
    if (r.view == ViewKind::kItem || r.view == ViewKind::kFocus) {
      r.object = g.find_object(v.item);
      if (!r.object.valid()) throw Error("render: scene " + request.scene + " has no object '" + v.item + "'");
    }
    const ViewPlan plan = plan_view(g, state, r);
    std::vector<ViewPlan> plans = {plan};
    std::vector<std::string> picture_captions = {v.caption};
    if (r.view == ViewKind::kPlatform) {
      const std::vector<PlatformPicture> pictures =
          platform_pictures(g, state, r.platform, plan.side, r.width, r.height);
      std::vector<ViewPlan> parts = part_plans(g, geometry(entry), state, r, plan);
      for (std::size_t k = 0; k < parts.size(); ++k) {
        plans.push_back(std::move(parts[k]));
        picture_captions.push_back(part_caption(pictures[k + 1], v.platform));
      }
    }
    std::size_t zooms_so_far = 0;  // zoom names run on across the pictures of one view
    for (std::size_t k = 0; k < plans.size(); ++k) {
      plans[k].first_zoom = zooms_so_far;
      drawn.push_back(draw_view(renderer, g, state, plans[k], v.marks != MarkKind::kNone, geometry(entry)));
      out.triangles += drawn.back().triangles;
      const ViewImages& images = drawn.back();
      const std::string role = role_of(r.view);
      roles.push_back(role);
      captions.push_back(picture_captions[k]);
      if (!images.marked.empty()) {
        roles.push_back(role + "_marked");
        captions.push_back(join_words(picture_captions[k], zoomed_caption(images, zooms_so_far)));
      }
      for (std::size_t z = 0; z < images.zooms.size(); ++z) {
        roles.push_back(role + "_zoom");
        captions.push_back(zoom_caption(zooms_so_far + z, images.zooms[z]));
      }
      zooms_so_far += images.zooms.size();
    }
  }
  return out;
}

}  // namespace mtg::render
