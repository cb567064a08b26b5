#pragma once
// The live progress line of `mtg run` (stderr): done/total, SR and IP so far, retries.

#include <cstdint>
#include <string>

namespace mtg::orchestrator {

class Progress {
 public:
  Progress(std::int64_t total, std::int64_t done, bool enabled);
  void record(bool success, double ip, bool scored);
  void retry() { ++retries_; }
  void draw(bool final = false);

 private:
  std::int64_t total_, done_;
  std::int64_t scored_ = 0, successes_ = 0;
  double ip_sum_ = 0.0;
  std::int64_t retries_ = 0;
  bool enabled_, tty_;
  int last_percent_ = -1;
};

}  // namespace mtg::orchestrator
