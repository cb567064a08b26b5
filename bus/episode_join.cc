#include "bus/episode_join.h"

#include "bus/channels.h"

namespace mtg::bus {

EpisodeJoin::EpisodeJoin(bus::Bus& bus, std::string run_id, Ready ready)
    : run_id_(std::move(run_id)), ready_(std::move(ready)) {
  bus.subscribe<mtg::episode_start_t>(bus::kEpisodeStart,
                                      [this](const std::string&, const mtg::episode_start_t& m) { on_start(m); });
  bus.subscribe<mtg::episode_truth_t>(bus::kEpisodeTruth,
                                      [this](const std::string&, const mtg::episode_truth_t& m) { on_truth(m); });
}

EpisodeJoin::Halves* EpisodeJoin::slot(const mtg::header_t& h) {
  if (!run_id_.empty() && h.run_id != run_id_) return nullptr;
  const Key key{h.run_id, episode_of(h)};
  if (const auto s = started_.last(key); s && *s >= h.attempt) return nullptr;
  // Bounded: a half whose other half was lost waits until thousands of others came after it.
  if (waiting_.size() >= kWaitingKept && waiting_.count(key) == 0) waiting_.erase(waiting_.begin());
  Halves& halves = waiting_[key];
  if (halves.attempt > h.attempt) return nullptr;
  if (halves.attempt < h.attempt) halves = Halves{h.attempt, std::nullopt, std::nullopt};
  return &halves;
}

void EpisodeJoin::complete(const Key& key) {
  const auto it = waiting_.find(key);
  if (it == waiting_.end() || !it->second.start || !it->second.truth) return;
  const Halves halves = std::move(it->second);
  waiting_.erase(it);
  started_.add(key, halves.attempt);
  ready_(*halves.start, *halves.truth);
}

void EpisodeJoin::on_start(const mtg::episode_start_t& start) {
  Halves* halves = slot(start.header);
  if (halves == nullptr || halves->start) return;  // stale or a duplicate
  halves->start = start;
  complete({start.header.run_id, episode_of(start.header)});
}

void EpisodeJoin::on_truth(const mtg::episode_truth_t& truth) {
  Halves* halves = slot(truth.header);
  if (halves == nullptr || halves->truth) return;
  halves->truth = truth;
  complete({truth.header.run_id, episode_of(truth.header)});
}

}  // namespace mtg::bus
