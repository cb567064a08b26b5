#include "orchestrator/run/run_folder_check.h"
#include "orchestrator/cli/cluster_commands.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <map>
#include <set>

#include <nlohmann/json.hpp>

#include "bus/authenticator.h"
#include "bus/bus.h"
#include "bus/channels.h"
#include "bus/header.h"
#include "bus/process/faults.h"
#include "bus/process/identity.h"
#include "bus/process/subprocess.h"
#include "bus/url.h"
#include "core/util/error.h"
#include "mtg/heartbeat_t.hpp"
#include "mtg/run_control_t.hpp"
#include "mtg/run_info_t.hpp"
#include "orchestrator/remote/gather.h"
#include "orchestrator/remote/session_rules.h"
#include "orchestrator/remote/tcp_hub.h"

namespace mtg::cli {

int run_gather(const GatherCliOptions& o) {
  orchestrator::check_run_folder(o.run);  // it writes episodes/ and results.sqlite: never through a link
  orchestrator::remote::GatherOptions g;
  g.run = o.run;
  for (const auto& f : o.from) g.from.emplace_back(f);
  g.bus = !o.no_bus;
  g.bus_url = o.bus_url.empty() ? "" : bus::normalize_url(o.bus_url);
  g.bus_key = o.bus_key;
  g.wait_s = o.wait_s;
  const auto r = orchestrator::remote::gather_recordings(g);
  std::printf("%s: %d recording(s) were in the run folder, %d copied, %d received from workers (%.1f MB); %zu missing\n",
              o.run.c_str(), r.already, r.copied, r.received, static_cast<double>(r.bytes) / 1e6, r.missing.size());
  for (const auto& line : r.missing) std::fprintf(stderr, "  %s\n", line.c_str());
  return r.missing.empty() ? 0 : 1;
}

int run_worker(WorkerCliOptions o) {
  auto& w = o.worker;
  if (w.bus_url.empty()) throw Error("mtg worker: --bus <shared LCM URL> is required");
  w.bus_url = bus::normalize_url(w.bus_url);
  if (!w.local_url.empty()) w.local_url = bus::normalize_url(w.local_url);
  if (w.local_url == w.bus_url) {
    throw Error("mtg worker: the host bus (--local-url " + w.local_url + ") must differ from the shared bus");
  }
  if (w.dir.empty()) w.dir = (std::filesystem::current_path() / "mtg-worker").string();
  w.dir = std::filesystem::absolute(w.dir).lexically_normal().string();
  w.vlm_args = o.vlm.to_args();
  w.drop_chunk_every = std::max(0, process::fault_setting("drop_chunk"));
  // hold_results_in_array_task:K holds only in Slurm array task K (the Slurm test's lost node).
  const int held_task = process::fault_setting("hold_results_in_array_task");
  const char* array_task = std::getenv("SLURM_ARRAY_TASK_ID");
  w.hold_results = process::fault_setting("hold_results") > 0 ||
                   (held_task >= 0 && array_task != nullptr && std::atoi(array_task) == held_task);
  return orchestrator::remote::run_worker(w);
}

int run_status(const StatusOptions& o) {
  const std::string url = bus::normalize_url(o.bus_url.empty() ? bus::default_url() : o.bus_url);
  bus::Bus bus(url);
  const bool keyed = !o.bus_key.empty() || std::getenv("MTG_BUS_KEY") != nullptr;
  if (keyed) bus.authenticate(bus::shared_bus_authenticator(o.bus_key));
  // With the key, only what answers this status's own challenge counts: a beat or announcement
  // sent before it asked may be a replay of a worker or run that is gone (session_rules.h).
  const std::string nonce = bus::draw_session_token();
  std::map<std::string, mtg::heartbeat_t> workers;
  std::map<std::string, mtg::run_info_t> runs;
  std::set<std::string> unanswered;  // workers heard only in beats that do not answer the challenge
  bus.subscribe<mtg::heartbeat_t>(bus::kHeartbeat, [&](const std::string&, const mtg::heartbeat_t& m) {
    if (m.role != "worker") return;
    if (keyed && m.echo != nonce) {
      unanswered.insert(m.header.sender);
      return;
    }
    workers[m.header.sender] = m;
  });
  bus.subscribe<mtg::run_info_t>(bus::kRunInfo, [&](const std::string&, const mtg::run_info_t& m) {
    if (keyed && m.echo != nonce) return;
    runs[m.header.run_id] = m;
  });
  bus::HeaderStamper stamp("", process::sender_id("status"));
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(o.listen_s);
  auto next_probe = std::chrono::steady_clock::now();
  while (std::chrono::steady_clock::now() < end) {
    if (keyed && std::chrono::steady_clock::now() >= next_probe) {
      mtg::run_control_t probe{};
      probe.header = stamp.next({}, 0, "control");
      probe.command = orchestrator::remote::kStatusProbe;
      probe.argument = nonce;
      bus.publish(bus::kControl, probe);
      next_probe += std::chrono::milliseconds(500);  // datagrams get lost: ask again
    }
    bus.handle_once(50);
  }
  for (const auto& [id, w] : workers) unanswered.erase(id);
  if (workers.empty() && runs.empty()) {
    const std::string rejected =
        bus.rejected() > 0 ? "; " + std::to_string(bus.rejected()) + " message(s) were not signed with this key" : "";
    throw Error("nothing heard on " + url + " in " + std::to_string(o.listen_s).substr(0, 3) +
                " s: no coordinator or worker (same URL? " +
                (bus::parse_tcpq(url) ? "" : "multicast routed? ") + "same --bus-key? docs/multihost.md)" + rejected);
  }
  auto sr = [](const mtg::run_info_t& r) { return r.scored > 0 ? 100.0 * static_cast<double>(r.successes) / static_cast<double>(r.scored) : 0.0; };
  auto ip = [](const mtg::run_info_t& r) { return r.scored > 0 ? r.ip_sum / static_cast<double>(r.scored) : 0.0; };
  if (o.json) {
    nlohmann::json j = {{"bus", url},          {"verified", keyed},      {"rejected", bus.rejected()},
                        {"unanswered", unanswered.size()},
                        {"runs", nlohmann::json::array()}, {"workers", nlohmann::json::array()}};
    for (const auto& [id, r] : runs) {
      j["runs"].push_back({{"run", id}, {"coordinator", r.header.sender}, {"state", r.state}, {"planned", r.planned},
                           {"finished", r.finished}, {"errors", r.errors}, {"in_flight", r.in_flight},
                           {"workers", r.workers}, {"episodes_per_min", r.episodes_per_min}, {"sr", sr(r)},
                           {"ip", ip(r)}, {"agents", r.agents}});
    }
    for (const auto& [id, w] : workers) {
      j["workers"].push_back({{"worker", id}, {"host", w.host}, {"run", w.header.run_id}, {"status", w.status},
                              {"capacity", w.capacity}, {"in_flight", w.in_flight}});
    }
    std::cout << j.dump() << '\n';
    return 0;
  }
  std::printf("bus %s%s\n", url.c_str(), keyed ? "" : " (unverified: no --bus-key)");
  for (const auto& [id, r] : runs) {
    std::printf("run %s (%s): %s, %lld/%lld finished (%lld errors), %d in flight on %d workers, %.0f episodes/min\n",
                id.c_str(), r.header.sender.c_str(), r.state.c_str(), static_cast<long long>(r.finished),
                static_cast<long long>(r.planned), static_cast<long long>(r.errors), r.in_flight, r.workers,
                r.episodes_per_min);
    std::printf("  SR %.1f %%  IP %.1f  over %lld scored episodes\n", sr(r), ip(r), static_cast<long long>(r.scored));
  }
  std::printf("%zu worker(s)\n", workers.size());
  if (!unanswered.empty()) {
    std::printf("  (%zu more heard in heartbeats that did not answer this status: replayed, or another mtg version; "
                "left out)\n", unanswered.size());
  }
  for (const auto& [id, w] : workers) {
    std::printf("  %-16s %-9s %d/%d in flight  run %s  (%s)\n", w.host.c_str(), w.status.c_str(), w.in_flight,
                w.capacity, w.header.run_id.empty() ? "-" : w.header.run_id.c_str(), id.c_str());
  }
  return 0;
}

void run_hub(const HubOptions& o) {
  const auto argv = orchestrator::remote::hub_command(o.port);
  orchestrator::remote::check_hub_port(o.port);
  std::printf("mtg hub: LCM TCP hub on port %d; every host joins with --bus %s (stop: Ctrl-C)\n", o.port,
              orchestrator::remote::hub_url(process::host_name(), o.port).c_str());
  std::fflush(stdout);
  if (o.quiet) {
    const int null = ::open("/dev/null", O_WRONLY);
    if (null >= 0) ::dup2(null, 1);
  }
  process::exec_process(argv);
}

}  // namespace mtg::cli
