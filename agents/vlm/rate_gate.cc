#include "agents/vlm/rate_gate.h"

#include <algorithm>

namespace mtg::vlm {

LocalRateGate::LocalRateGate(RateLimits limits) : limits_(limits) {
  limits_.window += std::min(limits.window / 20, std::chrono::milliseconds(1000));
}

std::int64_t LocalRateGate::acquire(const std::string& bucket, int tokens) {
  std::unique_lock lock(mutex_);
  const std::int64_t id = next_id_++;
  if (limits_.unlimited()) return id;
  RateWindow& w = windows_[bucket];
  for (;;) {
    const auto now = RateClock::now();
    const auto wait = w.wait_for(limits_, tokens, now);
    if (wait <= RateClock::duration::zero()) break;
    changed_.wait_for(lock, wait);
  }
  w.admit(id, tokens, RateClock::now());
  return id;
}

void LocalRateGate::done(const std::string& bucket, std::int64_t permit, int tokens) {
  std::lock_guard lock(mutex_);
  if (limits_.unlimited()) return;
  windows_[bucket].settle(permit, tokens);
  changed_.notify_all();
}

void LocalRateGate::pause(const std::string& bucket, double ms) {
  std::lock_guard lock(mutex_);
  windows_[bucket].pause_until(RateClock::now() + std::chrono::milliseconds(static_cast<long long>(ms)));
  changed_.notify_all();
}

}  // namespace mtg::vlm
