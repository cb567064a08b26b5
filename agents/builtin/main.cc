// A built-in agent process: oracle, random, replay or script (agents/builtin/policies.h).

#include <CLI/CLI.hpp>

#include "agents/builtin/policies.h"
#include "agents/common/agent_host.h"
#include "bus/bus.h"
#include "bus/error_events.h"
#include "bus/process/service_loop.h"
#include "bus/url.h"
#include "core/util/error.h"
#include "core/util/log.h"

int main(int argc, char** argv) {
  CLI::App app{"mtg built-in agent"};
  std::string url = mtg::bus::default_url();
  std::string spec, run_id;
  app.add_option("--url", url, "LCM URL");
  app.add_option("--agent", spec, "oracle, random, replay:<run dir> or script:<file>")->required();
  app.add_option("--run", run_id, "serve only this run ('' = every run)");
  std::string truth_key;
  app.add_option("--truth-key-file", truth_key, "the run's answer key (episode answers travel sealed; bus/truth_seal.h)");
  CLI11_PARSE(app, argc, argv);
  mtg::log::set_role("agent " + spec);
  mtg::process::install_stop_signals();
  try {
    mtg::bus::Bus bus(url);
    if (!truth_key.empty()) {
      bus.seal_truths(std::make_shared<const mtg::bus::TruthSeal>(mtg::bus::TruthSeal::from_file(truth_key)));
    }
    mtg::bus::HeaderStamper stamp(run_id, mtg::process::sender_id("agent"));
    mtg::agents::AgentHost host(bus, stamp, spec, mtg::agents::make_builtin_policy(spec), run_id);
    mtg::process::ServiceLoop loop(bus, stamp, mtg::bus::agent_role(spec), 64);
    loop.run([&] { loop.set_in_flight(host.in_flight()); });
  } catch (const std::exception& e) {
    mtg::log::error(e.what());
    return 1;
  }
  return 0;
}
