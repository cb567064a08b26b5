#include "core/util/rate_window.h"

#include <algorithm>

namespace mtg {

void RateWindow::expire(const RateLimits& limits, RateClock::time_point now) {
  while (!log_.empty() && log_.front().at + limits.window <= now) log_.pop_front();
}

RateClock::duration RateWindow::wait_for(const RateLimits& limits, int tokens, RateClock::time_point now) {
  expire(limits, now);
  RateClock::time_point ready = std::max(now, paused_until_);
  if (limits.rpm > 0 && static_cast<int>(log_.size()) >= limits.rpm) {
    // The call that must leave the window first: the (size - rpm + 1)-th oldest.
    ready = std::max(ready, log_[log_.size() - static_cast<std::size_t>(limits.rpm)].at + limits.window);
  }
  if (limits.tpm > 0) {
    long long used = 0;
    for (const Entry& e : log_) used += e.tokens;
    // A call bigger than the whole budget waits for an empty window rather than forever.
    const long long need = std::min<long long>(tokens, limits.tpm);
    for (const Entry& e : log_) {
      if (used + need <= limits.tpm) break;
      used -= e.tokens;
      ready = std::max(ready, e.at + limits.window);
    }
  }
  return ready - now;
}

void RateWindow::admit(std::int64_t id, int tokens, RateClock::time_point now) {
  // Kept in time order: `now` never goes backwards on a steady clock.
  log_.push_back({id, now, tokens});
}

void RateWindow::settle(std::int64_t id, int tokens) {
  for (Entry& e : log_) {
    if (e.id == id) e.tokens = tokens;
  }
}

void RateWindow::pause_until(RateClock::time_point until) { paused_until_ = std::max(paused_until_, until); }

}  // namespace mtg
