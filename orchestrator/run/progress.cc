#include "orchestrator/run/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace mtg::orchestrator {

Progress::Progress(std::int64_t total, std::int64_t done, bool enabled)
    : total_(total), done_(done), done_at_start_(done), enabled_(enabled), tty_(isatty(2) != 0),
      started_(std::chrono::steady_clock::now()) {}

void Progress::record(const std::string& agent, bool success, double ip, bool scored) {
  ++done_;
  if (!scored) return;
  for (Tally* t : {&all_, &by_agent_[agent]}) {
    ++t->scored;
    t->successes += success ? 1 : 0;
    t->ip_sum += ip;
  }
}

std::string Progress::Tally::text() const {
  const double sr = scored ? 100.0 * static_cast<double>(successes) / static_cast<double>(scored) : 0.0;
  const double ip = scored ? ip_sum / static_cast<double>(scored) : 0.0;
  char buf[64];
  std::snprintf(buf, sizeof buf, "SR %5.1f %%  IP %5.1f", sr, ip);
  return buf;
}

std::string Progress::duration_text(double seconds) {
  const auto s = static_cast<long long>(std::llround(std::max(0.0, seconds)));
  char buf[32];
  if (s >= 3600) {
    std::snprintf(buf, sizeof buf, "%lldh%02lldm", s / 3600, (s % 3600) / 60);
  } else if (s >= 60) {
    std::snprintf(buf, sizeof buf, "%lldm%02llds", s / 60, s % 60);
  } else {
    std::snprintf(buf, sizeof buf, "%llds", s);
  }
  return buf;
}

void Progress::draw(bool final) {
  if (!enabled_ || total_ == 0) return;
  const int percent = static_cast<int>(100 * done_ / total_);
  if (!tty_ && !final && percent / 10 == last_percent_ / 10) return;  // logs: a line per 10 %
  if (!tty_ && done_ == last_drawn_) return;  // the final line of a log already written at 100 %
  last_drawn_ = done_;
  last_percent_ = percent;
  constexpr int kWidth = 30;
  const int filled = static_cast<int>(kWidth * done_ / total_);
  std::string bar(static_cast<std::size_t>(filled), '#');
  bar.append(static_cast<std::size_t>(kWidth - filled), '.');
  // The rate of this invocation (a resume does not count what was done before it).
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
  const auto ran = static_cast<double>(done_ - done_at_start_);
  std::string pace;
  if (ran > 0 && elapsed >= 1.0) {  // the first second's rate says little
    const double rate = ran / elapsed;
    char buf[64];
    std::snprintf(buf, sizeof buf, "  %.1f ep/s", rate);
    pace = buf;
    if (!final && done_ < total_) pace += "  ETA " + duration_text(static_cast<double>(total_ - done_) / rate);
  }
  std::string scores = "  " + all_.text();
  if (by_agent_.size() > 1) {
    scores.clear();
    for (const auto& [agent, t] : by_agent_) scores += "  " + agent + ": " + t.text();
  }
  // On a terminal the line is redrawn in place; clear what a longer earlier line left.
  std::fprintf(stderr, "%s[%s] %lld/%lld episodes%s%s  retries %lld%s%s", tty_ ? "\r" : "", bar.c_str(),
               static_cast<long long>(done_), static_cast<long long>(total_), pace.c_str(), scores.c_str(),
               static_cast<long long>(retries_), tty_ ? "\033[K" : "", (tty_ && !final) ? "" : "\n");
  std::fflush(stderr);
}

}  // namespace mtg::orchestrator
