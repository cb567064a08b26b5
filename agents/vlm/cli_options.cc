// The model options on a command line: CLI11 only, so `mtg`'s front (orchestrator/cli/main.cc)
// compiles it without linking the adapters.
#include <CLI/CLI.hpp>

#include "agents/vlm/options.h"

namespace mtg::vlm {

void add_vlm_options(CLI::App& app, VlmOptions& o, bool with_workers) {
  app.add_option("--vlm-config", o.config_file, "model settings (JSON; docs/vlm.md)");
  app.add_option("--cache", o.cache_file, "response cache (default $MTG_CACHE_DIR or ~/.cache/mtg/vlm-cache.sqlite)");
  app.add_flag("--cache-only", o.cache_only, "answer only from the response cache; a miss fails the call");
  app.add_flag("--no-cache", o.no_cache, "neither read nor write the response cache");
  app.add_option("--key-file", o.key_file, "file holding the API key (else the provider's environment variable)");
  app.add_option("--rpm", o.rpm, "requests per window allowed, shared by all adapters (0 = unlimited)");
  app.add_option("--tpm", o.tpm, "tokens per window allowed (0 = unlimited)");
  app.add_option("--rate-window", o.rate_window_s, "the rate window in seconds (default 60)");
  app.add_option("--prompts", o.prompts_dir, "prompt template folder (default: the shipped v1)");
  app.add_option("--prices", o.prices_file, "price table (JSON; default: the shipped table)");
  app.add_option("--base-url", o.base_url, "API base URL (default: the provider's, or its *_BASE_URL variable)");
  if (with_workers) app.add_option("--workers", o.workers, "model calls in flight at once");
}

}  // namespace mtg::vlm
