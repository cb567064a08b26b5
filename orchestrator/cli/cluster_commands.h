#pragma once
// `mtg worker` and `mtg status` (docs/multihost.md).

#include <string>

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

int run_worker(WorkerCliOptions options);
int run_status(const StatusOptions& options);

}  // namespace mtg::cli
