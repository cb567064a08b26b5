#pragma once
// Messages of an attempt that has not started here yet, held until its start comes.
//
// udpm keeps each sender's order, not the order across senders, even on one host: the
// orchestrator's episode start can reach an agent after the scene-graph service's first
// observation of that episode (the service had the start first and answered at once). Seen in
// about one `mtg bench runtime` run in five: the agent dropped the observation as stale and the
// attempt waited out its time-out; the judge dropped a first state update and failed the attempt
// as a lost message. A host holds such early messages here and handles them when the start comes.
//
// Only messages with no start yet are held: a host forgets an episode's messages when any start
// of it arrives (its own or another agent's), so messages of episodes that are not its own do not
// accumulate. Bounded all the same: past `max_held` the oldest go.

#include <cstddef>
#include <deque>
#include <string>
#include <vector>

#include "mtg/header_t.hpp"

namespace mtg::bus {

template <class Msg>
class EarlyMessages {
 public:
  explicit EarlyMessages(std::size_t max_held) : max_held_(max_held) {}

  void hold(const Msg& m) {
    if (held_.size() >= max_held_) held_.pop_front();
    held_.push_back(m);
  }

  /// The messages held for the attempt `start` begins, in arrival order; forgets them and those of
  /// the episode's other attempts.
  std::vector<Msg> take(const mtg::header_t& start) {
    std::vector<Msg> out;
    std::deque<Msg> kept;
    for (Msg& m : held_) {
      const mtg::header_t& h = m.header;
      if (h.run_id != start.run_id || h.episode_id != start.episode_id) {
        kept.push_back(std::move(m));
      } else if (h.attempt == start.attempt) {
        out.push_back(std::move(m));
      }
    }
    held_.swap(kept);
    return out;
  }

  std::size_t size() const { return held_.size(); }

 private:
  std::size_t max_held_;
  std::deque<Msg> held_;
};

}  // namespace mtg::bus
