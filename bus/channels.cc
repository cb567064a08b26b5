#include "bus/channels.h"

namespace mtg::bus {

const char* episode_channel(EpisodeStream stream) {
  switch (stream) {
    case EpisodeStream::kObservation: return "MTG_OBS";
    case EpisodeStream::kAction: return "MTG_ACT";
    case EpisodeStream::kState: return "MTG_STATE";
    case EpisodeStream::kJudge: return "MTG_JUDGE";
  }
  return "MTG_UNKNOWN";
}

bool is_episode_channel(const std::string& channel, EpisodeStream stream) { return channel == episode_channel(stream); }

}  // namespace mtg::bus
