#include "bus/replay_window.h"

#include <algorithm>

namespace mtg::bus {

bool ReplayWindow::take(const Nonce& session, std::uint64_t number, std::int64_t delivery) {
  const std::lock_guard lock(mutex_);
  // LCM hands one datagram to every matching subscription in turn.
  if (delivery >= 0 && last_.delivery == delivery && last_.number == number && last_.session == session) return true;
  if (number == 0) return false;  // senders start at 1
  auto it = sessions_.find(session);
  if (it == sessions_.end()) {
    if (sessions_.size() >= kSessionsKept) {
      sessions_.erase(std::min_element(sessions_.begin(), sessions_.end(), [](const auto& a, const auto& b) {
        return a.second.last_heard < b.second.last_heard;
      }));
    }
    it = sessions_.emplace(session, Session{}).first;
  }
  Session& s = it->second;
  if (number > s.highest) {
    const std::uint64_t advance = number - s.highest;
    if (advance >= kWindow) {
      s.taken.reset();
    } else {
      for (std::uint64_t n = s.highest + 1; n < number; ++n) s.taken.reset(n % kWindow);
    }
    s.highest = number;
  } else if (s.highest - number >= kWindow || s.taken.test(number % kWindow)) {
    return false;
  }
  s.taken.set(number % kWindow);
  s.last_heard = ++heard_;
  last_ = {session, number, delivery};
  return true;
}

std::size_t ReplayWindow::sessions() const {
  const std::lock_guard lock(mutex_);
  return sessions_.size();
}

}  // namespace mtg::bus
