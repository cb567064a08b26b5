#pragma once
// The rate gate of an adapter process in a run: permits come from the run's one governor
// (services/governor) over MTG_RATE, so every adapter process of the run shares one budget per
// provider and model. Worker threads block in acquire(); the bus thread sends their requests and
// receives grants (pump() from the service loop). A request without a grant is sent again every
// 2 s, so a lost message or a restarted governor only delays calls.

#include <chrono>
#include <condition_variable>
#include <deque>
#include <map>
#include <mutex>
#include <string>

#include "agents/vlm/rate_gate.h"
#include "bus/bus.h"
#include "bus/header.h"
#include "mtg/rate_limit_t.hpp"

namespace mtg::vlm {

class BusRateGate : public RateGate {
 public:
  BusRateGate(bus::Bus& bus, bus::HeaderStamper& stamp, RateLimits limits);
  std::int64_t acquire(const std::string& bucket, int tokens) override;
  void done(const std::string& bucket, std::int64_t permit, int tokens) override;
  void pause(const std::string& bucket, double ms) override;
  /// Bus thread: sends what the workers queued and repeats unanswered requests.
  void pump();
  /// Wakes every waiting worker (shutdown); later acquires return at once.
  void cancel();

 private:
  struct Waiting {
    std::string bucket;
    int tokens = 0;
    std::chrono::steady_clock::time_point sent{};
    bool granted = false;
  };
  mtg::rate_limit_t message(const std::string& action, const std::string& bucket, std::int64_t id, int tokens,
                            int wait_ms) const;
  void on_message(const mtg::rate_limit_t& m);

  bus::Bus& bus_;
  bus::HeaderStamper& stamp_;
  RateLimits limits_;
  std::mutex mutex_;
  std::condition_variable granted_;
  std::map<std::int64_t, Waiting> waiting_;
  std::deque<mtg::rate_limit_t> outbox_;
  std::int64_t next_id_ = 0;
  bool cancelled_ = false;
};

}  // namespace mtg::vlm
