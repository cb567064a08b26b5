#pragma once
// The run's rate-limit governor (MTG_RATE, protocol in lcmtypes/rate_limit_t.lcm): one queue and
// one sliding window per bucket ("<provider>:<model>"), requests granted first come, first
// served as the window allows. The limits travel in each request (every adapter of a run has the
// same settings). Duplicated requests are answered once more with the same grant, never admitted
// twice, so a lost grant costs a resend and not the budget.

#include <chrono>
#include <deque>
#include <map>
#include <string>
#include <utility>

#include "bus/bus.h"
#include "bus/header.h"
#include "core/util/rate_window.h"
#include "mtg/rate_limit_t.hpp"

namespace mtg::services {

class Governor {
 public:
  Governor(bus::Bus& bus, bus::HeaderStamper& stamp);
  /// Grants what the windows allow now. Call often (the service loop's idle).
  void tick();
  int waiting() const;

 private:
  using RequestKey = std::pair<std::string, std::int64_t>;  // requester, request id
  struct Bucket {
    RateLimits limits;
    RateWindow window;
    std::deque<mtg::rate_limit_t> queue;
  };
  void on_message(const mtg::rate_limit_t& m);
  void grant(const mtg::rate_limit_t& request, int wait_ms);

  bus::Bus& bus_;
  bus::HeaderStamper& stamp_;
  std::map<std::string, Bucket> buckets_;
  std::map<RequestKey, RateClock::time_point> queued_;  // -> when it was first asked for
  std::map<RequestKey, std::int64_t> granted_;          // -> the window entry id it was admitted as
  std::int64_t next_entry_ = 0;
};

}  // namespace mtg::services
