#include "bus/header.h"

#include <limits>

namespace mtg::bus {

mtg::header_t HeaderStamper::next(EpisodeId episode, std::int32_t attempt, const std::string& stream) {
  mtg::header_t h = with_seq(episode, attempt, 0);
  h.seq = next_seq_[{episode.value(), attempt, stream}]++;
  return h;
}

mtg::header_t HeaderStamper::with_seq(EpisodeId episode, std::int32_t attempt, std::int64_t seq) const {
  mtg::header_t h{};
  h.run_id = run_id_;
  h.episode_id = episode.value();
  h.attempt = attempt;
  h.seq = seq;
  h.sender = sender_;
  h.schema_version = kSchemaVersion;
  return h;
}

void HeaderStamper::forget_episode(EpisodeId episode) {
  const auto first = next_seq_.lower_bound({episode.value(), std::numeric_limits<std::int32_t>::min(), std::string()});
  auto last = first;
  while (last != next_seq_.end() && std::get<0>(last->first) == episode.value()) ++last;
  next_seq_.erase(first, last);
}

std::string schema_mismatch(const mtg::header_t& header, const std::string& what) {
  return what + " from " + header.sender + " has schema version " + std::to_string(header.schema_version) +
         "; this build speaks " + std::to_string(kSchemaVersion);
}

std::optional<mtg::header_t> peek_header(std::span<const std::uint8_t> message) {
  if (message.size() < 8) return std::nullopt;
  mtg::header_t h{};
  const int len = static_cast<int>(message.size());
  if (h._decodeNoHash(message.data(), 8, len - 8) < 0) return std::nullopt;
  return h;
}

SequenceTracker::Verdict SequenceTracker::observe(const mtg::header_t& header) {
  const auto key = std::make_tuple(header.run_id, header.sender, header.episode_id, header.attempt);
  const auto it = last_seq_.find(key);
  if (it == last_seq_.end()) {
    last_seq_[key] = header.seq;
    return header.seq == 0 ? Verdict::kInOrder : Verdict::kGap;
  }
  if (header.seq <= it->second) return Verdict::kDuplicate;
  const bool gap = header.seq != it->second + 1;
  it->second = header.seq;
  return gap ? Verdict::kGap : Verdict::kInOrder;
}

void SequenceTracker::forget_episode(const std::string& run_id, EpisodeId episode) {
  for (auto it = last_seq_.begin(); it != last_seq_.end();) {
    const bool same = std::get<0>(it->first) == run_id && std::get<2>(it->first) == episode.value();
    it = same ? last_seq_.erase(it) : std::next(it);
  }
}

}  // namespace mtg::bus
