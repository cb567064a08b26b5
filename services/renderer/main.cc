// Renderer service: answers render requests with encoded images of the world state
// (docs/render.md). One headless GL context per process; scenes load on first use.

#include <CLI/CLI.hpp>

#include "bus/bus.h"
#include "bus/process/service_loop.h"
#include "bus/url.h"
#include "core/util/log.h"
#include "services/renderer/render_host.h"

int main(int argc, char** argv) {
  CLI::App app{"mtg renderer service"};
  std::string url = mtg::bus::default_url();
  std::string profile = "replica_cad", run_id;
  mtg::render::RendererOptions options;
  app.add_option("--url", url, "LCM URL");
  app.add_option("--profile", profile, "scene profile");
  app.add_option("--run", run_id, "serve only this run ('' = every run)");
  app.add_option("--max-texture", options.max_texture_size, "largest texture edge kept on the GPU (pixels)")
      ->check(CLI::Range(16, 8192));
  app.add_option("--encode-jobs", options.encode_jobs, "threads encoding one reply's images (0 = one per core)")
      ->check(CLI::Range(0, 256));
  CLI11_PARSE(app, argc, argv);
  mtg::log::set_role("renderer");
  mtg::process::install_stop_signals();
  try {
    mtg::bus::Bus bus(url);
    mtg::bus::HeaderStamper stamp(run_id, mtg::process::sender_id("renderer"));
    mtg::render::ImageRenderer renderer(profile, options);
    mtg::services::RenderHost host(bus, stamp, renderer, run_id);
    mtg::process::ServiceLoop loop(bus, stamp, "renderer", 1);
    loop.run();
  } catch (const std::exception& e) {
    mtg::log::error(e.what());
    return 1;
  }
  return 0;
}
