// Episode judge service: scores episodes from the bus alone (docs/runtime.md).

#include <CLI/CLI.hpp>

#include "bus/bus.h"
#include "bus/process/service_loop.h"
#include "bus/url.h"
#include "core/util/log.h"
#include "services/judge/judge_host.h"

int main(int argc, char** argv) {
  CLI::App app{"mtg episode judge"};
  std::string url = mtg::bus::default_url();
  std::string profile = "replica_cad", run_id;
  app.add_option("--url", url, "LCM URL");
  app.add_option("--profile", profile, "scene profile");
  std::string rules = "reached_and_seen";
  app.add_option("--platform-rules", rules, "how platforms are read (graph::PlatformRules): as the run's tasks were planned")
      ->check(CLI::IsMember({"reached_and_seen", "whole_surface"}));
  app.add_option("--run", run_id, "judge only this run ('' = every run)");
  std::string truth_key;
  app.add_option("--truth-key-file", truth_key, "the run's answer key (episode answers travel sealed; bus/truth_seal.h)");
  CLI11_PARSE(app, argc, argv);
  mtg::log::set_role("judge");
  mtg::process::install_stop_signals();
  try {
    mtg::bus::Bus bus(url);
    if (!truth_key.empty()) {
      bus.seal_truths(std::make_shared<const mtg::bus::TruthSeal>(mtg::bus::TruthSeal::from_file(truth_key)));
    }
    mtg::bus::HeaderStamper stamp(run_id, mtg::process::sender_id("judge"));
    mtg::graph::SceneCache scenes(profile, mtg::graph::platform_rules_from_string(rules, "--platform-rules"));
    mtg::services::JudgeHost host(bus, stamp, scenes, run_id);
    mtg::process::ServiceLoop loop(bus, stamp, "judge", 64);
    loop.run([&] { loop.set_in_flight(host.in_flight()); });
  } catch (const std::exception& e) {
    mtg::log::error(e.what());
    return 1;
  }
  return 0;
}
