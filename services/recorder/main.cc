// Bus recorder: appends every message of the bus to an LCM event log (services/recorder/recorder.h).
// It sends heartbeats like every service but ignores run_control "shutdown": the orchestrator
// stops it last, with a signal, so it records the other services' last messages.

#include <CLI/CLI.hpp>

#include <chrono>
#include <csignal>

#include "bus/bus.h"
#include "bus/header.h"
#include "bus/process/service_loop.h"
#include "bus/url.h"
#include "core/util/log.h"
#include "services/recorder/recorder.h"

int main(int argc, char** argv) {
  CLI::App app{"mtg bus recorder (an lcm-logger with a deep queue)"};
  std::string url = mtg::bus::default_url(), out, run_id;
  app.add_option("--url", url, "LCM URL");
  app.add_option("--run", run_id, "record only this run's messages ('' = everything on the bus)");
  app.add_option("file", out, "event log to append to")->required();
  CLI11_PARSE(app, argc, argv);
  mtg::log::set_role("recorder");
  mtg::process::install_stop_signals();
  // A file-size limit (`ulimit -f`) is a full disk to the recorder: without this the kernel's
  // SIGXFSZ kills it mid-event; ignored, write(2) says EFBIG and the recording is cut back whole.
  std::signal(SIGXFSZ, SIG_IGN);
  try {
    mtg::bus::Bus bus(url);
    mtg::bus::HeaderStamper stamp(run_id, mtg::process::sender_id("recorder"));
    mtg::services::Recorder recorder(bus, stamp, out, run_id);
    if (recorder.repaired_bytes() > 0) {
      mtg::log::warn("cut a torn last event (" + std::to_string(recorder.repaired_bytes()) + " bytes) off " + out +
                     ": the recorder before this one was killed while writing it");
    }
    mtg::process::ServiceLoop loop(bus, stamp, "recorder", 1, /*obeys_shutdown=*/false);
    auto next_flush = std::chrono::steady_clock::now();
    loop.run([&] {
      if (std::chrono::steady_clock::now() < next_flush) return;
      recorder.flush();  // a killed run keeps what was recorded up to 100 ms ago
      next_flush += std::chrono::milliseconds(100);
    });
    // Stopped last, after the services: record until the bus has been quiet for 20 ms.
    while (bus.handle_once(20)) {
    }
    recorder.flush();
    mtg::log::info("recorded " + std::to_string(recorder.events()) + " messages in " + out);
  } catch (const std::exception& e) {
    mtg::log::error(e.what());
    return 1;
  }
  return 0;
}
