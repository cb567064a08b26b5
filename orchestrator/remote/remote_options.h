#pragma once
// How a coordinator (`mtg run --remote`) deals with its workers (docs/multihost.md).

#include <string>

#include "orchestrator/remote/recordings_place.h"

namespace mtg::orchestrator::remote {

struct RemoteOptions {
  /// Workers that must have joined before the first lease (so a run spreads from the start).
  int min_workers = 1;
  /// How long to wait for them before giving up with an error.
  double worker_wait_s = 600.0;
  /// A lease not renewed for this long is re-issued elsewhere (workers renew every second).
  double lease_ttl_s = 5.0;
  /// The shared bus's key file ("" = $MTG_BUS_KEY): every message between hosts is signed with it.
  std::string bus_key;
  /// Where each attempt's recording goes (the plan's, parsed).
  RecordingsPlace recordings;
};

}  // namespace mtg::orchestrator::remote
