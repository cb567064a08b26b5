#include "bus/header.h"

namespace mtg::bus {

mtg::header_t HeaderStamper::next(std::int64_t episode_id, std::int32_t attempt, const std::string& stream) {
  mtg::header_t h{};
  h.run_id = run_id_;
  h.episode_id = episode_id;
  h.attempt = attempt;
  h.seq = next_seq_[{stream, episode_id, attempt}]++;
  h.sender = sender_;
  h.schema_version = kSchemaVersion;
  return h;
}

SequenceTracker::Verdict SequenceTracker::observe(const mtg::header_t& header) {
  const auto key = std::make_tuple(header.sender, header.episode_id, header.attempt);
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

void SequenceTracker::forget_episode(std::int64_t episode_id) {
  for (auto it = last_seq_.begin(); it != last_seq_.end();) {
    it = std::get<1>(it->first) == episode_id ? last_seq_.erase(it) : std::next(it);
  }
}

}  // namespace mtg::bus
