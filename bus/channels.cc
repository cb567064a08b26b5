#include "bus/channels.h"

namespace mtg::bus {
namespace {

const char* prefix(EpisodeStream stream) {
  switch (stream) {
    case EpisodeStream::kObservation: return "MTG_OBS_E";
    case EpisodeStream::kAction: return "MTG_ACT_E";
    case EpisodeStream::kState: return "MTG_STATE_E";
    case EpisodeStream::kJudge: return "MTG_JUDGE_E";
  }
  return "MTG_UNKNOWN_E";
}

}  // namespace

std::string episode_channel(EpisodeStream stream, std::int64_t episode_id) {
  return prefix(stream) + std::to_string(episode_id);
}

std::string episode_channel_regex(EpisodeStream stream) {
  return std::string(prefix(stream)) + "[0-9]+";
}

bool is_episode_channel(const std::string& channel, EpisodeStream stream) {
  return channel.rfind(prefix(stream), 0) == 0;
}

}  // namespace mtg::bus
