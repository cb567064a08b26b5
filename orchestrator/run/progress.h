#pragma once
// The live progress line of `mtg run` (stderr): done/total, the rate and the time left, SR and IP
// so far (per agent when several run), retries. Display only: nothing here reaches the results.

#include <chrono>
#include <cstdint>
#include <map>
#include <string>

namespace mtg::orchestrator {

class Progress {
 public:
  Progress(std::int64_t total, std::int64_t done, bool enabled);
  void record(const std::string& agent, bool success, double ip, bool scored);
  void retry() { ++retries_; }
  void draw(bool final = false);

  /// "1m05s", "2h03m", "42s": the time left at the rate so far.
  static std::string duration_text(double seconds);

 private:
  struct Tally {
    std::int64_t scored = 0, successes = 0;
    double ip_sum = 0.0;
    std::string text() const;  // "SR  50.0 %  IP  62.5"
  };
  std::int64_t total_, done_, done_at_start_;
  Tally all_;
  std::map<std::string, Tally> by_agent_;
  std::int64_t retries_ = 0;
  bool enabled_, tty_;
  int last_percent_ = -1;
  std::int64_t last_drawn_ = -1;  // episodes done at the last line written (logs: never the same twice)
  std::chrono::steady_clock::time_point started_;
};

}  // namespace mtg::orchestrator
