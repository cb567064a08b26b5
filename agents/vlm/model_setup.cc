#include "agents/vlm/model_setup.h"

namespace mtg::vlm {

ModelSetup ModelSetup::make(const std::string& agent_spec, const VlmSettings& settings) {
  ModelSetup m;
  m.settings = settings;
  m.spec = parse_model_spec(agent_spec, settings.base_url);
  m.key = load_api_key(m.spec, settings.key_file);
  m.prompts = settings.prompts_dir.empty() ? PromptSet::builtin() : PromptSet::load(settings.prompts_dir);
  m.prices = settings.prices_file.empty() ? PriceTable::builtin() : PriceTable::from_file(settings.prices_file);
  if (!settings.no_cache) m.cache = std::make_unique<ResponseCache>(settings.resolved_cache_file());
  return m;
}

RateLimits ModelSetup::limits() const {
  return RateLimits{settings.rpm, settings.tpm,
                    std::chrono::milliseconds(static_cast<long long>(settings.rate_window_s * 1000.0))};
}

}  // namespace mtg::vlm
