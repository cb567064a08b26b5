// Renderer service: answers render requests with encoded images of the world state
// (docs/render.md). One headless GL context per process; scenes load on first use. One of a
// host's pool of renderers (core/render/render_pool.h) serves the requests of its own channel.

#include <CLI/CLI.hpp>

#include <cstdio>
#include <cstdlib>
#include <string>

#include "bus/bus.h"
#include "bus/channels.h"
#include "bus/process/service_loop.h"
#include "bus/url.h"
#include "core/render/gl/gl_context.h"
#include "core/util/log.h"
#include "core/util/parallel.h"
#include "services/renderer/encode_pipeline.h"
#include "services/renderer/render_host.h"

int main(int argc, char** argv) {
  CLI::App app{"mtg renderer service"};
  std::string url = mtg::bus::default_url();
  std::string profile = "replica_cad", run_id;
  mtg::render::RendererOptions options;
  int pool_index = 0, gpu = -1, draw_threads = 0;
  bool count_gpus = false;
  app.add_option("--url", url, "LCM URL");
  app.add_option("--profile", profile, "scene profile");
  std::string rules = "reached_and_seen";
  app.add_option("--platform-rules", rules, "how platforms are read (graph::PlatformRules): as the run's tasks were planned")
      ->check(CLI::IsMember({"reached_and_seen", "whole_surface"}));
  app.add_option("--run", run_id, "serve only this run ('' = every run)");
  app.add_option("--max-texture", options.max_texture_size, "largest texture edge kept on the GPU (pixels)")
      ->check(CLI::Range(16, 8192));
  app.add_option("--encode-jobs", options.encode_jobs, "threads encoding images (0 = one per core)")
      ->check(CLI::Range(0, 256));
  app.add_option("--pool-index", pool_index, "this renderer's place in the host's pool (its request channel)")
      ->check(CLI::Range(0, 255));
  app.add_option("--gpu", gpu, "the hardware EGL device to draw on (-1 = the first)")->check(CLI::Range(-1, 255));
  app.add_option("--draw-threads", draw_threads, "llvmpipe's threads (LP_NUM_THREADS; 0 = its default)")
      ->check(CLI::Range(0, 256));
  app.add_flag("--count-gpus", count_gpus, "print how many hardware GPUs EGL offers, and exit");
  CLI11_PARSE(app, argc, argv);
  if (count_gpus) {
    std::printf("%d\n", mtg::render::hardware_gl_devices());
    return 0;
  }
  // Before the context exists: llvmpipe reads it when it starts its rasteriser threads.
  if (draw_threads > 0) ::setenv("LP_NUM_THREADS", std::to_string(draw_threads).c_str(), 1);
  const std::string role = mtg::bus::renderer_role(pool_index);
  mtg::log::set_role(role);
  mtg::process::install_stop_signals();
  try {
    mtg::bus::Bus bus(url);
    mtg::bus::Bus out(url);  // the encoders publish from their threads
    mtg::bus::HeaderStamper stamp(run_id, mtg::process::sender_id(role));
    mtg::render::ImageRenderer renderer(profile, options, gpu,
                                        mtg::graph::platform_rules_from_string(rules, "--platform-rules"));
    const int encoders = mtg::jobs_or_cores(options.encode_jobs);
    // Frames of at most two requests per encoder wait: enough to keep every encoder busy.
    mtg::services::EncodePipeline pipeline(encoders, 2 * encoders);
    mtg::services::RenderHost host(bus, out, stamp, renderer, pipeline, run_id, pool_index);
    mtg::process::ServiceLoop loop(bus, stamp, role, 1);
    loop.run([&] { loop.set_in_flight(pipeline.unfinished()); });
  } catch (const std::exception& e) {
    mtg::log::error(e.what());
    return 1;
  }
  return 0;
}
