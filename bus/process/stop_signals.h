#pragma once
// SIGINT and SIGTERM as a request to stop: the handler only sets a process-wide flag, and the
// process's loop ends its work cleanly when it sees it (a service drains, a run stores what
// finished and prints how to resume).

namespace mtg::process {

/// From now on SIGINT/SIGTERM set the flag instead of ending the process.
void install_stop_signals();
/// SIGINT/SIGTERM end the process again (the flag keeps what it saw).
void restore_default_signals();
/// Whether SIGINT/SIGTERM arrived since install_stop_signals().
bool stop_signal_received();

}  // namespace mtg::process
