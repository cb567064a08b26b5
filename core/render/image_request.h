#pragma once
// What is asked of the renderer and what it answers, without GL: the renderer process converts
// render_request_t to these (bus/convert) and `mtg render` builds them from its options. Objects
// and platforms are named, because the asker's graph is not the renderer's; the names are resolved
// against the renderer's own graph of the scene.

#include <cstdint>
#include <string>
#include <vector>

#include "core/episode/state_delta.h"
#include "core/render/view.h"

namespace mtg::render {

/// One view asked for by name (ViewRequest holds the graph's ids instead).
struct ViewSpec {
  ViewKind view = ViewKind::kPlatform;
  std::string platform;  // platform views
  int side = -1;
  std::string item;      // item and focus views
  MarkKind marks = MarkKind::kNone;  // kNone: no marked copy
  int number = 0;        // item and focus views: the number drawn on the object (0: none)
  std::string caption;   // words for the image (EncodedImage::caption)
};

struct ImageRequest {
  std::string scene;
  std::string data_dir;
  int width = 640;
  int height = 480;
  std::string encoding = "png";
  episode::StateDelta state;     // default: the scene as the graph found it
  double min_region_size = 0.03;
  std::vector<ViewSpec> views;
};

struct EncodedImage {
  std::string role;  // view, view_marked, view_zoom, item, focus, topdown, topdown_marked
  std::string caption;
  std::string encoding;
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> bytes;
};

struct ImageReply {
  std::vector<EncodedImage> images;
  std::int64_t triangles = 0;
};

}  // namespace mtg::render
