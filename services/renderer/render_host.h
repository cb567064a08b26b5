#pragma once
// The renderer process's bus side: every render_request_t on its channel becomes one
// render_result_t with the encoded images, or with ok == false and a one-line error. A request
// that carries its observation gets the images in that observation, which the renderer
// publishes before the result (then without images); a view the attempt's observations carried
// before goes by reference (bus/observation_packing.h). A bad request never stops the process;
// the next one is served as usual.
//
// The drawing is done on the thread that handles the bus (it owns the GL context); the images are
// encoded and published by the encoders (encode_pipeline.h), on a bus of their own, while the next
// request is drawn. One renderer of a pool (render_pool.h) serves the requests of its channel.

#include <memory>
#include <mutex>
#include <string>

#include "bus/bus.h"
#include "bus/header.h"
#include "bus/observation_packing.h"
#include "core/render/image_renderer.h"
#include "core/util/stopwatch.h"
#include "mtg/render_request_t.hpp"
#include "mtg/render_result_t.hpp"
#include "services/renderer/encode_pipeline.h"

namespace mtg::services {

class RenderHost {
 public:
  /// Requests come from `bus` on `channel`; images and results go out on `out` (the same URL,
  /// a bus of its own: the encoders publish from their threads) through `encoders`.
  RenderHost(bus::Bus& bus, bus::Bus& out, bus::HeaderStamper& stamp, render::ImageRenderer& renderer,
             EncodePipeline& encoders, std::string run_id, int pool_index);
  /// Waits for the encoders to finish what they hold of this host's (their callbacks use it).
  ~RenderHost() { encoders_.finish_all(); }
  RenderHost(const RenderHost&) = delete;
  RenderHost& operator=(const RenderHost&) = delete;
  void on_request(const mtg::render_request_t& request);

 private:
  // On an encoder thread (or this one, for a failed request): the observation with its images,
  // then the result.
  void finish(const mtg::render_request_t& request, const render::DrawnReply* drawn, EncodePipeline::Bytes bytes,
              std::string error, const Stopwatch& since_request);

  int pool_index_ = 0;
  long received_ = 0;
  int dies_at_ = -1;  // test hook (MTG_FAULTS="renderer_dies:<pool index>"): dies on its 2nd request, once
  bus::Bus& out_;
  bus::HeaderStamper& stamp_;
  render::ImageRenderer& renderer_;
  EncodePipeline& encoders_;
  std::string run_id_;
  std::mutex publishing_;  // out_ and sent_ are shared by the encoders
  bus::SentImages sent_;   // per attempt in flight: the images its observations carried
};

}  // namespace mtg::services
