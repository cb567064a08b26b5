#pragma once
// The renderer process's bus side: every render_request_t of its run becomes one
// render_result_t with the encoded images, or with ok == false and a one-line error. A bad
// request never stops the process; the next one is served as usual.

#include <string>

#include "bus/bus.h"
#include "bus/header.h"
#include "mtg/render_request_t.hpp"
#include "services/renderer/renderer.h"

namespace mtg::services {

class RenderHost {
 public:
  RenderHost(bus::Bus& bus, bus::HeaderStamper& stamp, Renderer& renderer, std::string run_id);
  void on_request(const mtg::render_request_t& request);
  long served() const { return served_; }

 private:
  bus::Bus& bus_;
  bus::HeaderStamper& stamp_;
  Renderer& renderer_;
  std::string run_id_;
  long served_ = 0;
};

/// The bus-free request of a message.
ImageRequest to_image_request(const mtg::render_request_t& m);

}  // namespace mtg::services
