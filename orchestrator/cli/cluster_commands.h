#pragma once
// `mtg worker`, `mtg status` and `mtg hub` (docs/multihost.md).

#include <string>
#include <vector>

#include "agents/vlm/options.h"
#include "orchestrator/remote/worker.h"

namespace mtg::cli {

struct WorkerCliOptions {
  orchestrator::remote::WorkerOptions worker;
  vlm::VlmOptions vlm;  // host-local: key file, cache, settings, prompts, prices, base URL
};

struct StatusOptions {
  std::string bus_url;
  std::string bus_key;  // "" = $MTG_BUS_KEY; without either, messages are shown unverified
  double listen_s = 2.5;
  bool json = false;
};

struct HubOptions {
  int port = 7700;
  bool quiet = false;  // without the hub's once-a-second throughput line
};

struct GatherCliOptions {
  std::string run;
  std::vector<std::string> from;
  bool no_bus = false;
  std::string bus_url;
  std::string bus_key;
  double wait_s = 30.0;
};

int run_worker(WorkerCliOptions options);
/// `mtg gather RUN`: a multi-host run's recordings kept on workers or in a shared folder, into the
/// run folder (orchestrator/remote/gather.h).
int run_gather(const GatherCliOptions& options);
/// Becomes the stock LCM TCP hub (exec); returns only by throwing.
[[noreturn]] void run_hub(const HubOptions& options);
int run_status(const StatusOptions& options);

}  // namespace mtg::cli
