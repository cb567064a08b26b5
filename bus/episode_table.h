#pragma once
// What a host keeps per episode, keyed by (run, episode) and valid for one attempt: a newer
// attempt's start replaces the entry, and messages of any other attempt find nothing (they are
// stale or early). The judge, the scene-graph service and the agent host keep their episodes in
// one, so "which attempt is current" is decided in one place. T carries its own `int attempt`
// (hosts stamp their messages with it); the table sets it.

#include <cstdint>
#include <map>
#include <string>
#include <utility>

#include "bus/episode_id.h"
#include "mtg/header_t.hpp"

namespace mtg::bus {

template <class T>
class EpisodeTable {
 public:
  using Key = std::pair<std::string, EpisodeId>;  // (run id, episode)

  static Key key_of(const mtg::header_t& h) { return {h.run_id, episode_of(h)}; }

  /// Whether a start with header `h` begins a new attempt (none is kept, or an older one).
  bool is_new_attempt(const mtg::header_t& h) const {
    const auto it = entries_.find(key_of(h));
    return it == entries_.end() || it->second.attempt < h.attempt;
  }
  /// Keeps `value` as the episode's entry for `h.attempt`, replacing an older attempt's.
  T& start(const mtg::header_t& h, T value) {
    value.attempt = h.attempt;
    T& slot = entries_[key_of(h)];
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
  void erase(const Key& key) { entries_.erase(key); }
  std::size_t size() const { return entries_.size(); }
  auto begin() { return entries_.begin(); }
  auto end() { return entries_.end(); }

 private:
  std::map<Key, T> entries_;
};

}  // namespace mtg::bus
