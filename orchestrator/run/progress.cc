#include "orchestrator/run/progress.h"

#include <unistd.h>

#include <cstdio>

namespace mtg::orchestrator {

Progress::Progress(std::int64_t total, std::int64_t done, bool enabled)
    : total_(total), done_(done), enabled_(enabled), tty_(isatty(2) != 0) {}

void Progress::record(bool success, double ip, bool scored) {
  ++done_;
  if (!scored) return;
  ++scored_;
  successes_ += success ? 1 : 0;
  ip_sum_ += ip;
}

void Progress::draw(bool final) {
  if (!enabled_ || total_ == 0) return;
  const int percent = static_cast<int>(100 * done_ / total_);
  if (!tty_ && !final && percent / 10 == last_percent_ / 10) return;  // logs: a line per 10 %
  last_percent_ = percent;
  constexpr int kWidth = 30;
  const int filled = static_cast<int>(kWidth * done_ / total_);
  std::string bar(static_cast<std::size_t>(filled), '#');
  bar.append(static_cast<std::size_t>(kWidth - filled), '.');
  const double sr = scored_ ? 100.0 * static_cast<double>(successes_) / static_cast<double>(scored_) : 0.0;
  const double ip = scored_ ? ip_sum_ / static_cast<double>(scored_) : 0.0;
  std::fprintf(stderr, "%s[%s] %lld/%lld episodes  SR %5.1f %%  IP %5.1f  retries %lld%s", tty_ ? "\r" : "",
               bar.c_str(), static_cast<long long>(done_), static_cast<long long>(total_), sr, ip,
               static_cast<long long>(retries_), (tty_ && !final) ? "" : "\n");
  std::fflush(stderr);
}

}  // namespace mtg::orchestrator
