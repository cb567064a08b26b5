#pragma once
// Work split over threads where the result must not depend on how it was split: each index is
// computed on its own into its own slot, and the caller combines the slots in index order.

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <limits>
#include <mutex>
#include <thread>
#include <vector>

namespace mtg {

/// The threads `--jobs 0` means: the machine's cores (at least 1).
inline int default_jobs() { return std::max(1, static_cast<int>(std::thread::hardware_concurrency())); }
/// `jobs` where it is positive, else default_jobs() (a setting of 0 means one per core).
inline int jobs_or_cores(int jobs) { return jobs > 0 ? jobs : default_jobs(); }

/// Calls body(i) for every i in [0, n) on up to `jobs` threads (this one included). body must
/// touch only what belongs to index i. If bodies throw, the exception of the lowest index is
/// rethrown here, after every thread has stopped (the same error whatever the thread count;
/// indices after a failure may not run).
template <typename Body>
void parallel_for(std::size_t n, int jobs, const Body& body) {
  const std::size_t threads = std::min<std::size_t>(n, static_cast<std::size_t>(std::max(1, jobs)));
  if (threads <= 1) {
    for (std::size_t i = 0; i < n; ++i) body(i);
    return;
  }
  std::atomic<std::size_t> next{0};
  std::exception_ptr failure;
  std::size_t failed_at = std::numeric_limits<std::size_t>::max();
  std::mutex failure_mutex;
  auto work = [&] {
    for (std::size_t i = next++; i < n; i = next++) {
      try {
        body(i);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(failure_mutex);
        if (i < failed_at) {
          failure = std::current_exception();
          failed_at = i;
        }
        next = n;  // the others stop at their next index
      }
    }
  };
  std::vector<std::thread> pool;
  try {
    for (std::size_t t = 1; t < threads; ++t) pool.emplace_back(work);
  } catch (...) {  // no thread to be had: stop those started, then say why
    next = n;
    for (auto& t : pool) t.join();
    throw;
  }
  work();
  for (auto& t : pool) t.join();
  if (failure) std::rethrow_exception(failure);
}

}  // namespace mtg
