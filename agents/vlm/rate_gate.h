#pragma once
// Where a model call asks for permission to go. The adapter processes of a run use the bus
// governor (BusRateGate in agents/vlm/bus_rate_gate.h, served by mtg_governor); a single process
// (`mtg vlm ask`, L4 voting in `mtg tasks`) uses LocalRateGate. Both block the calling thread.

#include <condition_variable>
#include <cstdint>
#include <map>
#include <mutex>
#include <string>

#include "core/util/rate_window.h"

namespace mtg::vlm {

class RateGate {
 public:
  virtual ~RateGate() = default;
  /// Blocks until a call of `tokens` (estimate) to `bucket` may go; returns its permit id.
  virtual std::int64_t acquire(const std::string& bucket, int tokens) = 0;
  /// The call finished and really used `tokens`.
  virtual void done(const std::string& bucket, std::int64_t permit, int tokens) = 0;
  /// The provider said 429: nobody calls `bucket` for `ms`.
  virtual void pause(const std::string& bucket, double ms) = 0;
};

class LocalRateGate : public RateGate {
 public:
  /// The window is kept 5 % (at most 1 s) longer than the provider's, as in the governor.
  explicit LocalRateGate(RateLimits limits);
  std::int64_t acquire(const std::string& bucket, int tokens) override;
  void done(const std::string& bucket, std::int64_t permit, int tokens) override;
  void pause(const std::string& bucket, double ms) override;

 private:
  RateLimits limits_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::map<std::string, RateWindow> windows_;
  std::int64_t next_id_ = 0;
};

}  // namespace mtg::vlm
