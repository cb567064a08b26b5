#include "bus/process/stop_signals.h"

#include <csignal>

namespace mtg::process {
namespace {

// Signal handlers can only touch a lock-free flag; this is the one process-wide state.
volatile std::sig_atomic_t g_stop_signal = 0;

void on_signal(int) { g_stop_signal = 1; }

}  // namespace

void install_stop_signals() {
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
}

void restore_default_signals() {
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
}

bool stop_signal_received() { return g_stop_signal != 0; }

}  // namespace mtg::process
