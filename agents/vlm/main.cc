// A model agent process: answers the run's observations for one agent spec
// (openai:<model>, anthropic:<model>, gemini:<model>, openai-compatible:<url>:<model>) through
// the provider's API. docs/vlm.md.

#include <CLI/CLI.hpp>

#include "agents/common/agent_host.h"
#include "agents/vlm/bus_rate_gate.h"
#include "agents/vlm/model_client.h"
#include "agents/vlm/model_setup.h"
#include "agents/vlm/options.h"
#include "agents/vlm/vlm_policy.h"
#include "bus/bus.h"
#include "bus/error_events.h"
#include "bus/process/service_loop.h"
#include "bus/url.h"
#include "core/util/log.h"

int main(int argc, char** argv) {
  CLI::App app{"mtg model agent"};
  std::string url = mtg::bus::default_url();
  std::string spec, run_id;
  mtg::vlm::VlmOptions options;
  app.add_option("--url", url, "LCM URL");
  app.add_option("--agent", spec, "openai:<model>, anthropic:<model>, gemini:<model>, openai-compatible:<url>:<model>")
      ->required();
  app.add_option("--run", run_id, "serve only this run ('' = every run)");
  mtg::vlm::add_vlm_options(app, options, true);
  CLI11_PARSE(app, argc, argv);
  mtg::log::set_role("agent " + spec);
  mtg::process::install_stop_signals();
  try {
    mtg::vlm::ModelSetup setup = mtg::vlm::ModelSetup::make(spec, options.resolve());
    mtg::bus::Bus bus(url);
    mtg::bus::HeaderStamper stamp(run_id, mtg::process::sender_id("agent"));
    mtg::vlm::BusRateGate gate(bus, stamp, setup.limits());
    mtg::vlm::ModelClient client(setup.spec, setup.key, setup.settings, setup.prices, setup.cache.get(), &gate);
    auto policy = std::make_unique<mtg::vlm::VlmPolicy>(client, setup.prompts, setup.settings);
    mtg::log::info("serving " + setup.spec.spec() + " at " + setup.spec.base_url + ", prompts " +
                   setup.prompts.version + (setup.cache ? ", cache " + setup.cache->file().string() : ", no cache") +
                   (setup.settings.cache_only ? " (cache only)" : ""));
    {
      mtg::agents::AgentHost host(bus, stamp, spec, std::move(policy), run_id, setup.settings.workers);
      mtg::process::ServiceLoop loop(bus, stamp, mtg::bus::agent_role(spec), setup.settings.workers);
      loop.run([&] {
        gate.pump();
        host.poll();
        loop.set_in_flight(host.in_flight());
      });
      // Unblock workers waiting for a permit or a response before the host joins them.
      gate.cancel();
      client.cancel();
    }
  } catch (const std::exception& e) {
    mtg::log::error(e.what());
    return 1;
  }
  return 0;
}
