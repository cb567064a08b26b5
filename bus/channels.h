#pragma once
// Channel names (DESIGN.md §4): MTG_<TOPIC>, per-episode streams end in E<episode id>.

#include <cstdint>
#include <string>

namespace mtg::bus {

inline constexpr const char* kEpisodeStart = "MTG_EPISODE_START";
/// The goal and oracle plan of an episode: judge, scene-graph service and oracle only.
inline constexpr const char* kEpisodeTruth = "MTG_EPISODE_TRUTH";
inline constexpr const char* kEpisodeResult = "MTG_RESULT";
/// The recorder's acknowledgement that a result is in the recording (recorded_t).
inline constexpr const char* kRecorded = "MTG_RECORDED";
inline constexpr const char* kRenderRequest = "MTG_RENDER_REQ";
inline constexpr const char* kRenderResult = "MTG_RENDER_RES";
inline constexpr const char* kHeartbeat = "MTG_HEARTBEAT";
inline constexpr const char* kLease = "MTG_LEASE";
inline constexpr const char* kRunInfo = "MTG_RUN";
inline constexpr const char* kRecord = "MTG_RECORD";
inline constexpr const char* kRateLimit = "MTG_RATE";
inline constexpr const char* kControl = "MTG_CONTROL";
inline constexpr const char* kError = "MTG_ERROR";
inline constexpr const char* kSceneRequest = "MTG_SCENE_REQ";
inline constexpr const char* kSceneSummary = "MTG_SCENE_SUMMARY";
inline constexpr const char* kTaskSetRequest = "MTG_TASKSET_REQ";
inline constexpr const char* kTaskSetSummary = "MTG_TASKSET_SUMMARY";

/// Per-episode streams.
enum class EpisodeStream { kObservation, kAction, kState, kJudge };

/// e.g. episode_channel(kObservation, 12) == "MTG_OBS_E12".
std::string episode_channel(EpisodeStream stream, std::int64_t episode_id);
/// Regex matching that stream for every episode, e.g. "MTG_OBS_E[0-9]+".
std::string episode_channel_regex(EpisodeStream stream);
/// Whether `channel` is one episode's channel of that stream (e.g. "MTG_ACT_E7" for kAction).
bool is_episode_channel(const std::string& channel, EpisodeStream stream);

}  // namespace mtg::bus
