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

std::string render_request_channel(int pool_index) {
  return pool_index <= 0 ? std::string(kRenderRequest) : std::string(kRenderRequest) + "_" + std::to_string(pool_index);
}

std::string renderer_role(int pool_index) {
  return pool_index <= 0 ? std::string("renderer") : "renderer-" + std::to_string(pool_index);
}

std::optional<int> renderer_index(const std::string& role) {
  if (role == "renderer") return 0;
  const std::string prefix = "renderer-";
  if (role.size() <= prefix.size() || role.compare(0, prefix.size(), prefix) != 0) return std::nullopt;
  int k = 0;
  for (std::size_t i = prefix.size(); i < role.size(); ++i) {
    if (role[i] < '0' || role[i] > '9' || k > 100000) return std::nullopt;
    k = k * 10 + (role[i] - '0');
  }
  return k > 0 ? std::optional<int>(k) : std::nullopt;
}

std::string lease_channel(const std::string& worker_session) { return std::string(kLease) + "_" + worker_session; }

bool is_episode_channel(const std::string& channel, EpisodeStream stream) { return channel == episode_channel(stream); }

}  // namespace mtg::bus
