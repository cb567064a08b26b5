// Scene-graph service: holds the world state of every running episode, applies the agents'
// action keys and publishes observations, and state updates (docs/runtime.md).

#include <CLI/CLI.hpp>

#include "bus/bus.h"
#include "bus/process/service_loop.h"
#include "bus/url.h"
#include "core/util/log.h"
#include "services/scene_graph/episode_host.h"

int main(int argc, char** argv) {
  CLI::App app{"mtg scene-graph service"};
  std::string url = mtg::bus::default_url();
  std::string profile = "replica_cad", run_id;
  app.add_option("--url", url, "LCM URL");
  app.add_option("--profile", profile, "scene profile");
  std::string rules = "reached_and_seen";
  app.add_option("--platform-rules", rules, "how platforms are read (graph::PlatformRules): as the run's tasks were planned")
      ->check(CLI::IsMember({"reached_and_seen", "whole_surface"}));
  app.add_option("--run", run_id, "serve only this run ('' = every run)");
  std::string truth_key;
  app.add_option("--truth-key-file", truth_key, "the run's answer key (episode answers travel sealed; bus/truth_seal.h)");
  mtg::services::ImageOptions images;
  app.add_option("--image-width", images.width, "observation image width (pixels)")->check(CLI::Range(16, 8192));
  app.add_option("--image-height", images.height, "observation image height (pixels)")->check(CLI::Range(16, 8192));
  app.add_option("--image-encoding", images.encoding, "png or jpeg")->check(CLI::IsMember({"png", "jpeg"}));
  app.add_option("--render-timeout", images.timeout_s, "seconds to wait for the renderer before asking again");
  app.add_option("--renderers", images.renderers, "renderer processes on this host's bus (docs/render.md)")
      ->check(CLI::Range(1, 256));
  CLI11_PARSE(app, argc, argv);
  mtg::log::set_role("scene_graph");
  mtg::process::install_stop_signals();
  try {
    mtg::bus::Bus bus(url);
    if (!truth_key.empty()) {
      bus.seal_truths(std::make_shared<const mtg::bus::TruthSeal>(mtg::bus::TruthSeal::from_file(truth_key)));
    }
    mtg::bus::HeaderStamper stamp(run_id, mtg::process::sender_id("scene_graph"));
    mtg::graph::SceneCache scenes(profile, mtg::graph::platform_rules_from_string(rules, "--platform-rules"));
    mtg::services::EpisodeHost host(bus, stamp, scenes, run_id, mtg::services::FaultInjection::from_env(),
                                        images);
    mtg::process::ServiceLoop loop(bus, stamp, "scene_graph", 64);
    loop.run([&] {
      loop.set_in_flight(host.in_flight());
      host.check_render_timeouts();
    });
  } catch (const std::exception& e) {
    mtg::log::error(e.what());
    return 1;
  }
  return 0;
}
