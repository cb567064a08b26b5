#pragma once
// The rate-limit arithmetic shared by the bus governor (services/governor) and the in-process
// gate (agents/vlm/rate_gate.h): a sliding-window log of admitted calls per bucket. A call is admitted when, over the last `window`, the calls
// stay within rpm and their tokens within tpm; the estimate admitted with a call is replaced by
// what it really used once it finishes. A provider's 429 pauses the bucket. Time is passed in,
// so the arithmetic is tested without sleeping.

#include <chrono>
#include <cstdint>
#include <deque>
#include <map>
#include <string>

namespace mtg {

using RateClock = std::chrono::steady_clock;

struct RateLimits {
  int rpm = 0;  // calls per window; 0 = unlimited
  int tpm = 0;  // tokens per window; 0 = unlimited
  std::chrono::milliseconds window{60000};
  bool unlimited() const { return rpm <= 0 && tpm <= 0; }
};

class RateWindow {
 public:
  /// How long a call of `tokens` must still wait (zero = it may go now).
  RateClock::duration wait_for(const RateLimits& limits, int tokens, RateClock::time_point now);
  void admit(std::int64_t id, int tokens, RateClock::time_point now);
  /// The call's real token count, once known.
  void settle(std::int64_t id, int tokens);
  void pause_until(RateClock::time_point until);

 private:
  struct Entry {
    std::int64_t id;
    RateClock::time_point at;
    int tokens;
  };
  void expire(const RateLimits& limits, RateClock::time_point now);

  std::deque<Entry> log_;
  RateClock::time_point paused_until_{};
};

}  // namespace mtg
