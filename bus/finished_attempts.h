#pragma once
// The last attempts a process finished, per (run, episode): a bounded memory, so that a late or
// replayed message of a finished attempt is still known as old while what a process keeps does
// not grow with the episodes of a long run (docs/runtime.md, "What each process keeps"). Past
// `kept` episodes the one finished longest ago is forgotten: a message of it arriving after
// thousands of later episodes finished is taken as new, and the hosts' other checks (the run id,
// the orchestrator's own attempt book) still hold.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <string>
#include <utility>

#include "bus/episode_id.h"

namespace mtg::bus {

class FinishedAttempts {
 public:
  using Key = std::pair<std::string, EpisodeId>;  // (run id, episode)
  static constexpr std::size_t kDefaultKept = 4096;

  explicit FinishedAttempts(std::size_t kept = kDefaultKept) : kept_(kept) {}

  /// Remembers `attempt` of `key` as finished (the highest one, if several).
  void add(const Key& key, std::int32_t attempt) {
    auto [it, fresh] = attempts_.try_emplace(key, attempt);
    if (!fresh) {
      it->second = std::max(it->second, attempt);
      return;
    }
    order_.push_back(key);
    if (order_.size() > kept_) {
      attempts_.erase(order_.front());
      order_.pop_front();
    }
  }
  /// The highest attempt of `key` remembered as finished.
  std::optional<std::int32_t> last(const Key& key) const {
    const auto it = attempts_.find(key);
    return it == attempts_.end() ? std::nullopt : std::optional<std::int32_t>(it->second);
  }
  std::size_t size() const { return attempts_.size(); }

 private:
  std::size_t kept_;
  std::map<Key, std::int32_t> attempts_;
  std::deque<Key> order_;  // finished first first
};

}  // namespace mtg::bus
