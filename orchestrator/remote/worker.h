#pragma once
// `mtg worker`: one per host of a multi-host run (docs/multihost.md). It waits on the shared bus
// for a coordinator's run, starts that run's processes on this host (LocalRuntime, on a bus of
// its own in a network namespace of the worker's own, which nothing else of the host or the
// network reaches: bus/private_network.h), heartbeats its capacity, runs the episode attempts it is
// leased and renews those leases every second. A finished attempt goes back as its result plus
// its recording -- the attempt's messages on this host's bus, cut into chunks -- resent until the
// coordinator releases it. So images never cross hosts as single multicast messages, and a
// recording is stored only complete.
//
// Between hosts only small messages travel, plus the recordings (paced chunks). The rate
// governor's messages (MTG_RATE) are bridged both ways, so model adapters on every host share
// the coordinator's governor.

#include <string>
#include <vector>

namespace mtg::orchestrator::remote {

struct WorkerOptions {
  std::string bus_url;            // the shared bus (udpm, ttl=1 across hosts)
  std::string bus_key;            // its key file ("" = $MTG_BUS_KEY): messages are signed
  /// This host's bus for the run's processes (ttl=0). "" = the default group in a network
  /// namespace of the worker's own, or, where none can be made, a loopback port of its own.
  std::string local_url;
  std::string name;               // shown by `mtg status` ("" = host name)
  int capacity = 2;               // episodes at once
  std::string dir;                // per-run process logs and this host's recordings
  std::string data_dir;           // dataset root here ("" = the path the coordinator uses)
  std::string recorder = "mtg";
  int renderers = 0;              // renderer processes for runs with images (0 = render::default_renderers)
  std::vector<std::string> vlm_args;  // host-local adapter options: key file, cache, settings, prompts
  int chunk_bytes = 32 * 1024;    // one datagram each
  int chunks_per_round = 16;      // paced: at most this many chunks per 10 ms round
  bool once = false;              // leave after one run (tests, batch jobs)
  /// Join only this run ("" = the first announced). A worker started for one run (a Slurm array
  /// task) must not serve another coordinator on the same bus, and gives up when that run is
  /// not announced within kRunNotHeardS.
  std::string run_id;
  /// Test hook (MTG_FAULTS="drop_chunk:<n>"): the first sending of a recording skips every n-th
  /// chunk, as a lossy network would, so the coordinator must wait for the resend.
  int drop_chunk_every = 0;
  /// Test hook (MTG_FAULTS="hold_results:1"): finished attempts are never sent back, so the
  /// leases stay held until the host dies -- a host that crashes before delivering.
  bool hold_results = false;
};

/// How long a worker bound to one run (WorkerOptions::run_id) waits to hear it announced.
inline constexpr double kRunNotHeardS = 120.0;

/// Runs until SIGINT/SIGTERM (or after one run with `once`). @throws mtg::Error.
int run_worker(const WorkerOptions& options);

}  // namespace mtg::orchestrator::remote
