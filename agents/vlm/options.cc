#include "agents/vlm/options.h"

namespace mtg::vlm {

VlmSettings VlmOptions::resolve() const {
  VlmSettings s = config_file.empty() ? VlmSettings{} : VlmSettings::from_json_file(config_file);
  if (!cache_file.empty()) s.cache_file = cache_file;
  if (!key_file.empty()) s.key_file = key_file;
  if (!prompts_dir.empty()) s.prompts_dir = prompts_dir;
  if (!prices_file.empty()) s.prices_file = prices_file;
  if (!base_url.empty()) s.base_url = base_url;
  if (cache_only) s.cache_only = true;
  if (no_cache) s.no_cache = true;
  if (rpm >= 0) s.rpm = rpm;
  if (tpm >= 0) s.tpm = tpm;
  if (workers >= 0) s.workers = workers;
  if (rate_window_s > 0) s.rate_window_s = rate_window_s;
  s.validate();
  return s;
}

std::vector<std::string> VlmOptions::to_args() const {
  std::vector<std::string> a;
  auto text = [&](const char* flag, const std::string& v) {
    if (!v.empty()) a.insert(a.end(), {flag, v});
  };
  text("--vlm-config", config_file);
  text("--cache", cache_file);
  text("--key-file", key_file);
  text("--prompts", prompts_dir);
  text("--prices", prices_file);
  text("--base-url", base_url);
  if (cache_only) a.push_back("--cache-only");
  if (no_cache) a.push_back("--no-cache");
  if (rpm >= 0) a.insert(a.end(), {"--rpm", std::to_string(rpm)});
  if (tpm >= 0) a.insert(a.end(), {"--tpm", std::to_string(tpm)});
  if (workers >= 0) a.insert(a.end(), {"--workers", std::to_string(workers)});
  if (rate_window_s > 0) a.insert(a.end(), {"--rate-window", std::to_string(rate_window_s)});
  return a;
}

}  // namespace mtg::vlm
