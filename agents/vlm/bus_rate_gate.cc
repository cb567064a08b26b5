#include "agents/vlm/bus_rate_gate.h"

#include "bus/channels.h"

namespace mtg::vlm {

namespace {
constexpr auto kResend = std::chrono::seconds(2);
}

BusRateGate::BusRateGate(bus::Bus& bus, bus::HeaderStamper& stamp, RateLimits limits)
    : bus_(bus), stamp_(stamp), limits_(limits) {
  bus_.subscribe<mtg::rate_limit_t>(bus::kRateLimit,
                                    [this](const std::string&, const mtg::rate_limit_t& m) { on_message(m); });
}

mtg::rate_limit_t BusRateGate::message(const std::string& action, const std::string& bucket, std::int64_t id,
                                       int tokens, int wait_ms) const {
  mtg::rate_limit_t m{};
  m.action = action;
  m.bucket = bucket;
  m.requester = stamp_.sender();
  m.request_id = id;
  m.rpm = limits_.rpm;
  m.tpm = limits_.tpm;
  m.window_ms = static_cast<int32_t>(limits_.window.count());
  m.tokens = tokens;
  m.wait_ms = wait_ms;
  return m;
}

std::int64_t BusRateGate::acquire(const std::string& bucket, int tokens) {
  std::unique_lock lock(mutex_);
  const std::int64_t id = next_id_++;
  if (limits_.unlimited() || cancelled_) return id;
  waiting_[id] = Waiting{bucket, tokens, {}, false};
  granted_.wait(lock, [&] { return cancelled_ || waiting_.at(id).granted; });
  waiting_.erase(id);
  return id;
}

void BusRateGate::done(const std::string& bucket, std::int64_t permit, int tokens) {
  if (limits_.unlimited()) return;
  std::lock_guard lock(mutex_);
  outbox_.push_back(message("done", bucket, permit, tokens, 0));
}

void BusRateGate::pause(const std::string& bucket, double ms) {
  std::lock_guard lock(mutex_);
  outbox_.push_back(message("pause", bucket, -1, 0, static_cast<int>(ms)));
}

void BusRateGate::cancel() {
  {
    std::lock_guard lock(mutex_);
    cancelled_ = true;
  }
  granted_.notify_all();
}

void BusRateGate::pump() {
  std::deque<mtg::rate_limit_t> out;
  {
    std::lock_guard lock(mutex_);
    out.swap(outbox_);
    const auto now = std::chrono::steady_clock::now();
    for (auto& [id, w] : waiting_) {
      if (w.granted || now - w.sent < kResend) continue;
      w.sent = now;
      out.push_back(message("request", w.bucket, id, w.tokens, 0));
    }
  }
  for (auto& m : out) {
    m.header = stamp_.next({}, 0, "rate");
    bus_.publish(bus::kRateLimit, m);
  }
}

void BusRateGate::on_message(const mtg::rate_limit_t& m) {
  if (m.action != "grant" || m.requester != stamp_.sender()) return;
  {
    std::lock_guard lock(mutex_);
    const auto it = waiting_.find(m.request_id);
    if (it == waiting_.end()) return;
    it->second.granted = true;
  }
  granted_.notify_all();
}

}  // namespace mtg::vlm
