#include "services/renderer/render_host.h"

#include "bus/channels.h"
#include "core/util/error.h"
#include "core/util/hash.h"
#include "core/util/log.h"
#include "core/util/stopwatch.h"
#include "mtg/render_result_t.hpp"

namespace mtg::services {

ImageRequest to_image_request(const mtg::render_request_t& m) {
  ImageRequest r;
  r.scene = m.scene;
  r.data_dir = m.data_dir;
  r.width = m.width;
  r.height = m.height;
  r.encoding = m.encoding;
  r.state_json = m.state_json;
  if (m.min_region_size > 0.0) r.min_region_size = m.min_region_size;
  for (const mtg::render_view_t& v : m.views) r.views.push_back({v.view, v.platform, v.side, v.item, v.marks});
  return r;
}

RenderHost::RenderHost(bus::Bus& bus, bus::HeaderStamper& stamp, Renderer& renderer, std::string run_id)
    : bus_(bus), stamp_(stamp), renderer_(renderer), run_id_(std::move(run_id)) {
  bus_.subscribe<mtg::render_request_t>(bus::kRenderRequest, [this](const std::string&, const mtg::render_request_t& m) {
    if (run_id_.empty() || m.header.run_id == run_id_) on_request(m);
  });
}

void RenderHost::on_request(const mtg::render_request_t& request) {
  mtg::render_result_t out{};
  out.request_id = request.request_id;
  const Stopwatch watch;
  try {
    const ImageReply reply = renderer_.render(to_image_request(request));
    out.ok = true;
    out.triangles = reply.triangles;
    for (const EncodedImage& e : reply.images) {
      mtg::image_t img{};
      img.role = e.role;
      img.encoding = e.encoding;
      img.width = e.width;
      img.height = e.height;
      img.content_hash = to_hex(fnv1a64(e.bytes));
      img.data = e.bytes;
      img.nbytes = static_cast<int32_t>(img.data.size());
      out.images.push_back(std::move(img));
    }
  } catch (const std::exception& e) {
    out.ok = false;
    out.error = e.what();
    out.images.clear();
    log::warn("request " + std::to_string(request.request_id) + " of episode " +
              std::to_string(request.header.episode_id) + ": " + out.error);
  }
  out.n_images = static_cast<int32_t>(out.images.size());
  out.render_ms = watch.elapsed_ms();
  // The reply carries the requester's episode and attempt, so it is matched without any lookup.
  out.header = stamp_.next(request.header.episode_id, request.header.attempt, "render");
  out.header.run_id = request.header.run_id;
  bus_.publish(bus::kRenderResult, out);
  ++served_;
}

}  // namespace mtg::services
