// Rate-limit governor: one per run, shared by every model adapter process (docs/vlm.md).

#include <CLI/CLI.hpp>

#include "bus/bus.h"
#include "bus/process/service_loop.h"
#include "bus/url.h"
#include "core/util/log.h"
#include "services/governor/governor.h"

int main(int argc, char** argv) {
  CLI::App app{"mtg rate-limit governor"};
  std::string url = mtg::bus::default_url();
  std::string run_id, bus_key;
  app.add_option("--url", url, "LCM URL");
  app.add_option("--bus-key", bus_key, "key file of a bus shared between hosts (messages are signed)");
  app.add_option("--run", run_id, "the run it serves (for its heartbeats)");
  CLI11_PARSE(app, argc, argv);
  mtg::log::set_role("governor");
  mtg::process::install_stop_signals();
  try {
    mtg::bus::Bus bus(url);
    if (!bus_key.empty()) bus.authenticate(mtg::bus::shared_bus_authenticator(bus_key));
    mtg::bus::HeaderStamper stamp(run_id, mtg::process::sender_id("governor"));
    mtg::services::Governor governor(bus, stamp);
    mtg::process::ServiceLoop loop(bus, stamp, "governor", 1);
    loop.run([&] {
      governor.tick();
      loop.set_in_flight(governor.waiting());
    });
  } catch (const std::exception& e) {
    mtg::log::error(e.what());
    return 1;
  }
  return 0;
}
