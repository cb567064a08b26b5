// The human agent process: a person is the policy. It serves the play page (play_server.h) and
// answers each observation with the key the person chose there (docs/view.md, "Play").

#include <CLI/CLI.hpp>

#include "agents/builtin/policies.h"
#include "agents/common/agent_host.h"
#include "agents/human/play_desk.h"
#include "agents/human/play_server.h"
#include "bus/bus.h"
#include "bus/channels.h"
#include "bus/error_events.h"
#include "bus/process/service_loop.h"
#include "bus/url.h"
#include "core/util/log.h"

int main(int argc, char** argv) {
  CLI::App app{"mtg human agent: play episodes in the browser"};
  std::string url = mtg::bus::default_url();
  std::string run_id, host = "127.0.0.1", token_file, unix_socket;
  int port = 8780;
  app.add_option("--url", url, "LCM URL");
  app.add_option("--run", run_id, "serve only this run ('' = every run)");
  app.add_option("--host", host, "address of the play page (default 127.0.0.1: this machine only)");
  app.add_option("--port", port, "port of the play page");
  app.add_option("--token-file", token_file, "the page's token (needed with a --host beyond loopback)");
  app.add_option("--unix-socket", unix_socket, "serve the page on this Unix socket; --host/--port are where it is relayed from");
  CLI11_PARSE(app, argc, argv);
  mtg::log::set_role("agent human");
  mtg::process::install_stop_signals();
  try {
    mtg::bus::Bus bus(url);
    mtg::bus::HeaderStamper stamp(run_id, mtg::process::sender_id("agent"));
    auto desk_owner = std::make_unique<mtg::agents::PlayDesk>();
    mtg::agents::PlayDesk& desk = *desk_owner;
    mtg::agents::PlayServer server(desk);
    const std::string token = token_file.empty() ? "" : mtg::web::read_token_file(token_file);
    if (unix_socket.empty()) {
      server.start(host, port, token);
    } else {
      server.start_unix(unix_socket, host, port, token);
    }
    // The token stays out of the log: the run's folder may be shared.
    mtg::log::info("play at " + mtg::web::page_url({host, port, token.empty() ? "" : "<token>"}) +
                   (unix_socket.empty() ? "" : ", relayed to the socket " + unix_socket));
    // The judge's verdicts on the person's attempts, shown on the page after each episode.
    bus.subscribe<mtg::episode_result_t>(mtg::bus::kEpisodeResult,
                                         [&desk, &run_id](const std::string&, const mtg::episode_result_t& r) {
                                           if ((run_id.empty() || r.header.run_id == run_id) && r.agent == mtg::agents::kHumanAgent) {
                                             desk.verdict(r);
                                           }
                                         });
    // One worker thread: the person's answer is awaited there, never in the bus thread.
    mtg::agents::AgentHost agent(bus, stamp, "human", std::move(desk_owner), run_id, 1);
    // Declared after the host, so it runs first: the host's worker may be waiting for a person.
    struct ReleaseDesk {
      mtg::agents::PlayDesk& desk;
      ~ReleaseDesk() { desk.shutdown(); }
    } release{desk};
    mtg::process::ServiceLoop loop(bus, stamp, mtg::bus::agent_role("human"), 64);
    loop.run([&] {
      agent.poll();
      loop.set_in_flight(agent.in_flight());
    });
  } catch (const std::exception& e) {
    mtg::log::error(e.what());
    return 1;
  }
  return 0;
}
