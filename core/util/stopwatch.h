#pragma once
// Wall-clock measurement for telemetry and benchmarks only; logic never reads it.

#include <chrono>

namespace mtg {

class Stopwatch {
 public:
  Stopwatch() : start_(std::chrono::steady_clock::now()) {}
  double elapsed_ms() const {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_)
        .count();
  }
  void reset() { start_ = std::chrono::steady_clock::now(); }

 private:
  std::chrono::steady_clock::time_point start_;
};

/// Peak resident set size of this process in MiB (Linux VmHWM), 0 if unknown.
double peak_rss_mib();

}  // namespace mtg
