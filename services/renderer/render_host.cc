#include "services/renderer/render_host.h"

#include <cstdlib>
#include <optional>

#include "bus/channels.h"
#include "bus/convert.h"
#include "bus/process/faults.h"
#include "core/util/error.h"
#include "core/util/log.h"
#include "core/util/stopwatch.h"

namespace mtg::services {

RenderHost::RenderHost(bus::Bus& bus, bus::Bus& out, bus::HeaderStamper& stamp, render::ImageRenderer& renderer,
                       EncodePipeline& encoders, std::string run_id, int pool_index)
    : pool_index_(pool_index), dies_at_(process::fault_setting("renderer_dies")), out_(out), stamp_(stamp),
      renderer_(renderer), encoders_(encoders), run_id_(std::move(run_id)) {
  bus.subscribe<mtg::render_request_t>(bus::render_request_channel(pool_index), [this](const std::string&,
                                                                                     const mtg::render_request_t& m) {
    if (run_id_.empty() || m.header.run_id == run_id_) on_request(m);
  });
}

void RenderHost::on_request(const mtg::render_request_t& request) {
  const Stopwatch watch;
  if (++received_ == 2 && dies_at_ == pool_index_ && process::first_time_fault("renderer_dies")) {
    log::warn("fault injection: dying with request " + std::to_string(request.request_id) + " of episode " +
              std::to_string(request.header.episode_id) + " unanswered");
    std::_Exit(3);
  }
  // What the encoders need outlives this call: the request (its observation) and the frames.
  struct Drawn {
    mtg::render_request_t request;
    render::DrawnReply reply;
  };
  auto drawn = std::make_shared<Drawn>();
  try {
    drawn->reply = renderer_.draw(bus::from_message(request));
  } catch (const std::exception& e) {
    finish(request, nullptr, {}, e.what(), watch);
    return;
  }
  drawn->request = request;
  const Drawn* d = drawn.get();
  encoders_.submit(d->reply.images(), d->reply.encoding, drawn,
                   [this, d, watch](EncodePipeline::Bytes bytes, std::exception_ptr error) {
                     std::string why;
                     if (error) {
                       try {
                         std::rethrow_exception(error);
                       } catch (const std::exception& e) {
                         why = e.what();
                       }
                     }
                     finish(d->request, error ? nullptr : &d->reply, std::move(bytes), why, watch);
                   });
}

void RenderHost::finish(const mtg::render_request_t& request, const render::DrawnReply* drawn,
                        EncodePipeline::Bytes bytes, std::string error, const Stopwatch& since_request) {
  mtg::render_result_t out{};
  out.request_id = request.request_id;
  const auto failed = [&](const std::string& why) {
    out.ok = false;
    out.error = why;
    out.images.clear();
    log::warn("request " + std::to_string(request.request_id) + " of episode " +
              std::to_string(request.header.episode_id) + ": " + why);
  };
  // The images are copied into the messages here, on this encoder's thread, beside the others.
  std::optional<mtg::observation_t> obs;
  try {
    if (drawn == nullptr) throw Error(error);
    const render::ImageReply reply = render::encoded_reply(*drawn, std::move(bytes));
    out.ok = true;
    out.triangles = reply.triangles;
    for (const render::EncodedImage& e : reply.images) out.images.push_back(bus::to_message(e));
    if (request.with_observation) {
      // The images go to the agent in the observation, and nowhere else.
      obs = request.observation;
      obs->images = std::move(out.images);
      obs->n_images = static_cast<int32_t>(obs->images.size());
      out.images.clear();
      out.images_published = obs->n_images;
    }
  } catch (const std::exception& e) {
    failed(e.what());
  }
  // One encoder at a time from here: the publishing bus, and what each attempt's observations carried.
  const std::lock_guard<std::mutex> lock(publishing_);
  if (obs) {
    sent_.refer_to_earlier(*obs);
    try {
      out_.publish(bus::episode_channel(bus::EpisodeStream::kObservation), *obs);
    } catch (const std::exception& e) {
      sent_.forget(obs->header);  // nothing reached the agent: the attempt's later views go whole
      failed(e.what());
    }
  }
  out.n_images = static_cast<int32_t>(out.images.size());
  out.render_ms = since_request.elapsed_ms();  // drawn, waited for an encoder, encoded
  // The reply carries the requester's episode and attempt, so it is matched without any lookup,
  // and its request's seq: numbered as the requests are, with nothing kept per episode here.
  out.header = stamp_.with_seq(bus::episode_of(request.header), request.header.attempt, request.header.seq);
  out.header.run_id = request.header.run_id;
  try {
    out_.publish(bus::kRenderResult, out);
  } catch (const std::exception& e) {
    log::error("request " + std::to_string(request.request_id) + " of episode " +
               std::to_string(request.header.episode_id) + ": the result could not be sent: " + e.what());
  }
}

}  // namespace mtg::services
