#include "orchestrator/run/hang_rule.h"

#include <algorithm>

namespace mtg::orchestrator {

const char* to_string(Silence s) {
  switch (s) {
    case Silence::kBeating: return "beating";
    case Silence::kSlow: return "slow";
    case Silence::kHung: return "hung";
    case Silence::kRunaway: return "runaway";
  }
  return "?";
}

HangLimits hang_limits(double episode_timeout_s) {
  HangLimits l;
  l.hang_after_s = std::max(3.0, 0.8 * episode_timeout_s);
  l.runaway_after_s = std::max(l.hang_after_s, 2.0 * episode_timeout_s);
  return l;
}

Silence classify(const Quiet& q, const HangLimits& limits) {
  if (q.since_beat_s <= limits.hang_after_s) return Silence::kBeating;
  if (q.stopped || q.since_progress_s > limits.hang_after_s) return Silence::kHung;
  if (q.since_beat_s > limits.runaway_after_s) return Silence::kRunaway;
  return Silence::kSlow;
}

bool made_progress(const ThreadActivity& before, const ThreadActivity& now) {
  if (now.state == 'T' || now.state == 't' || now.state == 'Z' || now.state == 'X') return false;
  return now.cpu_seconds > before.cpu_seconds || now.state == 'R' || now.state == 'D';
}

}  // namespace mtg::orchestrator
