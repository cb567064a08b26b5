#pragma once
// One model call, done properly: the response cache first; then a permit from the rate gate;
// then the HTTP exchange, retried with back-off on 429/5xx/529/network errors and malformed
// bodies; then the answer, its tokens and its list price. Authentication, quota and billing
// errors stop the client: every later call fails at once with the same message, without HTTP.
// Thread-safe: an adapter answers several episodes at once through one client.

#include <atomic>
#include <condition_variable>
#include <mutex>
#include <span>
#include <string>

#include "agents/vlm/chat.h"
#include "agents/vlm/model_spec.h"
#include "agents/vlm/prices.h"
#include "agents/vlm/rate_gate.h"
#include "agents/vlm/response_cache.h"
#include "agents/vlm/secrets.h"
#include "agents/vlm/settings.h"

namespace mtg::vlm {

struct CallResult {
  bool ok = false;
  std::string text;          // the model's reply
  std::string error;         // why the call failed (one line, key redacted)
  bool stop_agent = false;   // the failure ends this agent (auth, quota, billing, unknown model)
  int input_tokens = 0;
  int output_tokens = 0;
  int images = 0;
  double cost_usd = 0.0;     // list price of this answer (also for a cache hit)
  double latency_ms = 0.0;   // telemetry: wall time of the call, retries and waits included
  bool cache_hit = false;
  int http_attempts = 0;
};

class ModelClient {
 public:
  /// `cache` and `gate` may be null (no cache; no rate limit). They must outlive the client.
  ModelClient(ModelSpec spec, ApiKey key, const VlmSettings& settings, PriceTable prices, ResponseCache* cache,
              RateGate* gate);
  CallResult call(std::span<const ChatMessage> messages);
  /// Aborts calls in flight and waits (for shutdown); later calls fail at once.
  void cancel();
  const ModelSpec& spec() const { return spec_; }
  const ApiKey& key() const { return key_; }

 private:
  CallResult stopped_result();
  bool sleep_ms(double ms);  // false when cancelled
  int estimate_tokens(std::span<const ChatMessage> messages) const;

  ModelSpec spec_;
  ApiKey key_;
  GenerationParams params_;
  VlmSettings settings_;
  PriceTable prices_;
  ResponseCache* cache_;
  RateGate* gate_;
  std::atomic<bool> cancelled_{false};
  std::mutex mutex_;
  std::condition_variable wake_;
  std::string stop_reason_;  // guarded by mutex_
};

}  // namespace mtg::vlm
