#pragma once
// What to do with a provider's response: use it, retry it (429, 5xx, 529, network trouble), fail
// this call, or stop the agent (authentication, billing and quota errors: every further call
// would fail the same way, and retrying would only spend the quota of someone else's key).
// And how long to wait before a retry: what the server asks for (Retry-After, retry-after-ms,
// the rate-limit reset headers, Gemini's RetryInfo), else exponential back-off with jitter.

#include <cstdint>
#include <string>

#include "agents/vlm/http_client.h"
#include "agents/vlm/model_spec.h"

namespace mtg::vlm {

enum class Outcome { kSuccess, kRetry, kFailCall, kStopAgent };

struct Classified {
  Outcome outcome = Outcome::kSuccess;
  std::string message;             // one line for logs and results (never the key)
  double server_delay_ms = -1.0;   // the delay the server asked for; -1 if none
};

Classified classify(const ModelSpec& spec, const HttpResponse& response);

struct Backoff {
  double base_s = 1.0;
  double cap_s = 60.0;
};

/// The wait before retry number `retry` (0 = the first retry). With a server delay, that delay
/// plus up to 10 % jitter; otherwise base * 2^retry, capped, with "equal jitter" (half fixed, half
/// random). The jitter is drawn from `jitter_seed` (a hash of the request), so parallel adapters
/// spread out without unseeded randomness.
double retry_delay_ms(const Classified& c, int retry, const Backoff& backoff, std::uint64_t jitter_seed);

/// The delay in a response's headers, in ms (-1 if none): retry-after-ms, retry-after (seconds or
/// an HTTP date), x-ratelimit-reset-requests/-tokens ("1s", "6m0s", "20ms"),
/// anthropic-ratelimit-requests-reset/-tokens-reset (RFC 3339).
double header_delay_ms(const HttpResponse& response);

}  // namespace mtg::vlm
