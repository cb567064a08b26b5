#pragma once
// An episode starts with two messages on two channels: its episode_truth_t (judge, scene-graph
// service, oracle) and its episode_start_t (everyone). The orchestrator publishes the truth first,
// but a subscriber does not depend on that: EpisodeJoin pairs them per (run, episode, attempt)
// and calls `ready` once both are there. A newer attempt replaces an older one still waiting;
// messages of other runs (when a run id is given) and of older attempts are ignored.

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <utility>

#include "bus/bus.h"
#include "bus/episode_id.h"
#include "bus/finished_attempts.h"
#include "mtg/episode_start_t.hpp"
#include "mtg/episode_truth_t.hpp"

namespace mtg::bus {

class EpisodeJoin {
 public:
  using Ready = std::function<void(const mtg::episode_start_t&, const mtg::episode_truth_t&)>;
  /// Subscribes to both channels on `bus`; `run_id` "" takes every run.
  EpisodeJoin(bus::Bus& bus, std::string run_id, Ready ready);

  /// Feeds a message by hand (tests, and hosts that receive them some other way).
  void on_start(const mtg::episode_start_t& start);
  void on_truth(const mtg::episode_truth_t& truth);
  /// Attempts waiting for their other half.
  std::size_t waiting() const { return waiting_.size(); }

 private:
  struct Halves {
    int attempt = -1;
    std::optional<mtg::episode_start_t> start;
    std::optional<mtg::episode_truth_t> truth;
  };
  /// The slot of (run, episode) for `attempt`, or null when that attempt is stale.
  Halves* slot(const mtg::header_t& h);
  using Key = std::pair<std::string, EpisodeId>;  // (run id, episode)
  void complete(const Key& key);

  std::string run_id_;
  Ready ready_;
  std::map<Key, Halves> waiting_;
  FinishedAttempts started_;  // last attempts handed out (bounded)
  static constexpr std::size_t kWaitingKept = 4096;  // halves whose other half never came
};

}  // namespace mtg::bus
