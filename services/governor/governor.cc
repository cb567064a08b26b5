#include "services/governor/governor.h"

#include <algorithm>

#include "bus/channels.h"

namespace mtg::services {

Governor::Governor(bus::Bus& bus, bus::HeaderStamper& stamp) : bus_(bus), stamp_(stamp) {
  bus_.subscribe<mtg::rate_limit_t>(bus::kRateLimit,
                                    [this](const std::string&, const mtg::rate_limit_t& m) { on_message(m); });
}

int Governor::waiting() const {
  int n = 0;
  for (const auto& [name, b] : buckets_) n += static_cast<int>(b.queue.size());
  return n;
}

void Governor::on_message(const mtg::rate_limit_t& m) {
  const RequestKey key{m.requester, m.request_id};
  Bucket& b = buckets_[m.bucket];
  if (m.action == "request") {
    // The window is kept a little longer than the provider's: a grant reaches the provider some
    // milliseconds later, and not every grant equally late (5 %, at most 1 s).
    const int window = m.window_ms > 0 ? m.window_ms : 60000;
    b.limits = RateLimits{m.rpm, m.tpm, std::chrono::milliseconds(window + std::min(window / 20, 1000))};
    if (granted_.count(key) != 0) {
      grant(m, 0);  // the grant was lost: the same permit again
    } else if (queued_.emplace(key, RateClock::now()).second) {
      b.queue.push_back(m);
    }
  } else if (m.action == "done") {
    if (const auto it = granted_.find(key); it != granted_.end()) {
      b.window.settle(it->second, m.tokens);
      granted_.erase(it);
    }
  } else if (m.action == "pause") {
    b.window.pause_until(RateClock::now() + std::chrono::milliseconds(m.wait_ms));
  }
}

void Governor::tick() {
  const auto now = RateClock::now();
  for (auto& [name, b] : buckets_) {
    while (!b.queue.empty()) {
      const mtg::rate_limit_t& head = b.queue.front();
      if (b.window.wait_for(b.limits, head.tokens, now) > RateClock::duration::zero()) break;
      const RequestKey key{head.requester, head.request_id};
      const std::int64_t entry = next_entry_++;
      b.window.admit(entry, head.tokens, now);
      granted_[key] = entry;
      const auto asked = queued_.extract(key);
      const auto waited = std::chrono::duration_cast<std::chrono::milliseconds>(now - asked.mapped()).count();
      grant(head, static_cast<int>(waited));
      b.queue.pop_front();
    }
  }
}

void Governor::grant(const mtg::rate_limit_t& request, int wait_ms) {
  mtg::rate_limit_t g = request;
  g.header = stamp_.next({}, 0, "rate");
  g.action = "grant";
  g.wait_ms = wait_ms;
  bus_.publish(bus::kRateLimit, g);
}

}  // namespace mtg::services
