#pragma once
// The renderer process's bus side: every render_request_t of its run becomes one
// render_result_t with the encoded images, or with ok == false and a one-line error. A request
// that carries its observation gets the images in that observation, which the renderer
// publishes before the result (then without images); a view the attempt's observations carried
// before goes by reference (bus/observation_packing.h). A bad request never stops the process;
// the next one is served as usual.

#include <string>

#include "bus/bus.h"
#include "bus/header.h"
#include "bus/observation_packing.h"
#include "core/render/image_renderer.h"
#include "mtg/render_request_t.hpp"

namespace mtg::services {

class RenderHost {
 public:
  RenderHost(bus::Bus& bus, bus::HeaderStamper& stamp, render::ImageRenderer& renderer, std::string run_id);
  void on_request(const mtg::render_request_t& request);
  long served() const { return served_; }

 private:
  bus::Bus& bus_;
  bus::HeaderStamper& stamp_;
  render::ImageRenderer& renderer_;
  std::string run_id_;
  bus::SentImages sent_;  // per attempt in flight: the images its observations carried
  long served_ = 0;
};


}  // namespace mtg::services
