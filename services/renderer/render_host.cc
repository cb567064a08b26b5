#include "services/renderer/render_host.h"

#include "bus/channels.h"
#include "bus/convert.h"
#include "core/util/error.h"
#include "core/util/log.h"
#include "core/util/stopwatch.h"
#include "mtg/render_result_t.hpp"

namespace mtg::services {

RenderHost::RenderHost(bus::Bus& bus, bus::HeaderStamper& stamp, render::ImageRenderer& renderer, std::string run_id)
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
    const render::ImageReply reply = renderer_.render(bus::from_message(request));
    out.ok = true;
    out.triangles = reply.triangles;
    for (const render::EncodedImage& e : reply.images) out.images.push_back(bus::to_message(e));
    if (request.with_observation) {
      // The images go to the agent in the observation, and nowhere else.
      mtg::observation_t obs = request.observation;
      obs.images = std::move(out.images);
      obs.n_images = static_cast<int32_t>(obs.images.size());
      sent_.refer_to_earlier(obs);
      out.images.clear();
      out.images_published = obs.n_images;
      try {
        bus_.publish(bus::episode_channel(bus::EpisodeStream::kObservation), obs);
      } catch (...) {
        sent_.forget(obs.header);  // nothing reached the agent: the attempt's later views go whole
        throw;
      }
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
  // The reply carries the requester's episode and attempt, so it is matched without any lookup,
  // and its request's seq: numbered as the requests are, with nothing kept per episode here.
  out.header = stamp_.with_seq(bus::episode_of(request.header), request.header.attempt, request.header.seq);
  out.header.run_id = request.header.run_id;
  bus_.publish(bus::kRenderResult, out);
  ++served_;
}

}  // namespace mtg::services
