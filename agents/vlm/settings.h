#pragma once
// How a model adapter talks to its model: generation parameters, what it sends, how it retries,
// its rate limits, cache and files. Read from a JSON file (every field optional; unknown fields
// are errors, so a typo never silently falls back to a default), then command-line overrides.

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace mtg::vlm {

struct VlmSettings {
  // generation
  double temperature = 0.0;
  int max_output_tokens = 256;
  int seed = -1;                    // sent where the API takes one (OpenAI); -1 = not sent
  // what is sent
  std::vector<std::string> image_roles = {"view_marked", "view_zoom", "item", "focus", "topdown_marked"};
  std::string image_detail = "low"; // OpenAI-style detail: "low", "high" or "auto"
  int image_max_side = 0;           // longer side in pixels, images above are shrunk; 0 = as rendered
  int history_steps = 0;            // earlier steps kept in the conversation; 0 = the whole episode
  int history_images = 1;           // the latest steps whose images stay in the conversation
  // transport
  double request_timeout_s = 120.0;
  double connect_timeout_s = 10.0;
  int max_attempts = 6;             // per call, for 429/5xx/529/network errors
  double backoff_base_s = 1.0;
  double backoff_cap_s = 60.0;
  double max_retry_wait_s = 300.0;  // a server asking to wait longer fails the call instead
  // shared rate limits (0 = unlimited), per provider and model
  int rpm = 0;
  int tpm = 0;
  double rate_window_s = 60.0;
  // files
  std::string cache_file;           // "" = $MTG_CACHE_DIR or ~/.cache/mtg, vlm-cache.sqlite
  bool cache_only = false;          // a cache miss fails the call instead of calling the API
  bool no_cache = false;
  std::string prompts_dir;          // "" = the shipped agents/vlm/prompts/v3 (compiled in)
  std::string prices_file;          // "" = the shipped agents/vlm/prices.json (compiled in)
  std::string key_file;             // "" = the provider's environment variable
  std::string base_url;             // "" = the provider's default (or its *_BASE_URL variable)
  int workers = 8;                  // calls in flight at once (episodes answered in parallel)

  /// @throws mtg::Error naming the file and field.
  static VlmSettings from_json_file(const std::string& file);
  /// What a run's answers depend on (generation, what is sent, prompts, prices, endpoint), for
  /// its provenance; transport and rate settings and the key file's path are left out.
  nlohmann::json provenance_json() const;
  /// Fails on impossible values. @throws mtg::Error naming the field.
  void validate() const;
  std::string resolved_cache_file() const;
};

}  // namespace mtg::vlm
