#pragma once
// What a command line says about model agents (`mtg run`, `mtg vlm`, `mtg tasks --voter`, and
// the adapter process): a settings file plus overrides. The orchestrator forwards the same
// options to every adapter it starts (to_args), so they all run with one configuration.

#include <string>
#include <vector>

#include "agents/vlm/settings.h"

namespace CLI {
class App;
}

namespace mtg::vlm {

struct VlmOptions {
  std::string config_file, cache_file, key_file, prompts_dir, prices_file, base_url;
  bool cache_only = false;
  bool no_cache = false;
  int rpm = -1, tpm = -1, workers = -1;  // -1 = as the settings file (or default) says
  double rate_window_s = -1.0;

  /// The settings file (or the defaults) with the overrides applied. @throws mtg::Error.
  VlmSettings resolve() const;
  /// The same options as adapter arguments.
  std::vector<std::string> to_args() const;
};

/// Adds --vlm-config, --cache, --cache-only, --no-cache, --key-file, --rpm, --tpm, --rate-window,
/// --prompts, --prices, --base-url (and --workers when `with_workers`).
void add_vlm_options(CLI::App& app, VlmOptions& options, bool with_workers);

}  // namespace mtg::vlm
