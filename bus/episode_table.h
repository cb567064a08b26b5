#pragma once
// What a host keeps per episode, keyed by (run, episode) and valid for one attempt: a newer
// attempt's start replaces the entry, and messages of any other attempt find nothing (they are
// stale or early). The judge, the scene-graph service and the agent host keep their episodes in
// one, so "which attempt is current" is decided in one place. T carries its own `int attempt`
// (hosts stamp their messages with it); the table sets it.
//
// Bounded (docs/runtime.md, "What each process keeps"): an episode erased when it is over is
// remembered only as (key, attempt) among the last few thousand (finished_attempts.h), so a late or replayed start of
// a finished attempt is still known as old; with max_entries, a table that is never told an
// episode ended (an agent's record of other agents' episodes) forgets its lowest keys first.

#include <cstdint>
#include <limits>
#include <map>
#include <string>
#include <utility>

#include "bus/episode_id.h"
#include "bus/finished_attempts.h"
#include "mtg/header_t.hpp"

namespace mtg::bus {

template <class T>
class EpisodeTable {
 public:
  using Key = std::pair<std::string, EpisodeId>;  // (run id, episode)
  explicit EpisodeTable(std::size_t max_entries = std::numeric_limits<std::size_t>::max())
      : max_entries_(max_entries) {}

  static Key key_of(const mtg::header_t& h) { return {h.run_id, episode_of(h)}; }

  /// Whether a start with header `h` begins a new attempt (none is kept, or an older one).
  bool is_new_attempt(const mtg::header_t& h) const {
    const auto it = entries_.find(key_of(h));
    if (it != entries_.end()) return it->second.attempt < h.attempt;
    const auto done = finished_.last(key_of(h));
    return !done || *done < h.attempt;
  }
  /// Keeps `value` as the episode's entry for `h.attempt`, replacing an older attempt's.
  T& start(const mtg::header_t& h, T value) {
    value.attempt = h.attempt;
    const Key key = key_of(h);
    if (entries_.size() >= max_entries_ && entries_.count(key) == 0) entries_.erase(entries_.begin());
    T& slot = entries_[key];
    slot = std::move(value);
    return slot;
  }
  /// The entry of h's episode when it is for h's attempt; null otherwise.
  T* current(const mtg::header_t& h) {
    const auto it = entries_.find(key_of(h));
    return it == entries_.end() || it->second.attempt != h.attempt ? nullptr : &it->second;
  }
  /// The entry of an episode whatever its attempt; null when none.
  T* find(const Key& key) {
    const auto it = entries_.find(key);
    return it == entries_.end() ? nullptr : &it->second;
  }
  /// Forgets the episode's entry, remembering its attempt as finished.
  void erase(const Key& key) {
    const auto it = entries_.find(key);
    if (it == entries_.end()) return;
    finished_.add(key, it->second.attempt);
    entries_.erase(it);
  }
  std::size_t size() const { return entries_.size(); }
  /// Finished attempts remembered (bounded: FinishedAttempts).
  std::size_t finished() const { return finished_.size(); }
  auto begin() { return entries_.begin(); }
  auto end() { return entries_.end(); }

 private:
  std::size_t max_entries_;
  std::map<Key, T> entries_;
  FinishedAttempts finished_;
};

}  // namespace mtg::bus
