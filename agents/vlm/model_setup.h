#pragma once
// Everything one model agent needs, built once from its spec and settings: where the API is, the
// key, the prompts, the prices and the response cache. The adapter process, `mtg vlm ask` and
// L4 voting all start from here.

#include <memory>
#include <string>

#include "agents/vlm/model_spec.h"
#include "agents/vlm/prices.h"
#include "agents/vlm/prompt.h"
#include "agents/vlm/response_cache.h"
#include "agents/vlm/secrets.h"
#include "agents/vlm/settings.h"
#include "core/util/rate_window.h"

namespace mtg::vlm {

struct ModelSetup {
  ModelSpec spec;
  VlmSettings settings;
  ApiKey key;
  PromptSet prompts;
  PriceTable prices;
  std::unique_ptr<ResponseCache> cache;  // null with no_cache

  /// @throws mtg::Error naming the spec, file or variable at fault.
  static ModelSetup make(const std::string& agent_spec, const VlmSettings& settings);
  RateLimits limits() const;
};

}  // namespace mtg::vlm
