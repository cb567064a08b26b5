#pragma once
// Channel names (DESIGN.md §4): MTG_<TOPIC>.

#include <optional>
#include <string>

namespace mtg::bus {

inline constexpr const char* kEpisodeStart = "MTG_EPISODE_START";
/// The goal and oracle plan of an episode: judge, scene-graph service and oracle only.
inline constexpr const char* kEpisodeTruth = "MTG_EPISODE_TRUTH";
inline constexpr const char* kEpisodeResult = "MTG_RESULT";
/// The recorder's acknowledgement that a result is in the recording (recorded_t).
inline constexpr const char* kRecorded = "MTG_RECORDED";
/// Render requests to the first (or only) renderer of a host; render_request_channel(k) names
/// the channel of renderer k of a pool.
inline constexpr const char* kRenderRequest = "MTG_RENDER_REQ";
inline constexpr const char* kRenderResult = "MTG_RENDER_RES";
inline constexpr const char* kHeartbeat = "MTG_HEARTBEAT";
/// Worker -> coordinator lease messages (renew); coordinator -> worker ones go on lease_channel().
inline constexpr const char* kLease = "MTG_LEASE";
/// A worker's renewal of all its leases at once (lease_renewal_t).
inline constexpr const char* kLeaseRenewal = "MTG_LEASE_RENEW";
inline constexpr const char* kRunInfo = "MTG_RUN";
inline constexpr const char* kRecord = "MTG_RECORD";
/// Where a worker keeps an attempt's recording (recording_ref_t), instead of its chunks.
inline constexpr const char* kRecordRef = "MTG_RECORD_REF";
/// A request for recordings a worker keeps (`mtg gather`; recording_request_t).
inline constexpr const char* kRecordRequest = "MTG_RECORD_REQ";
inline constexpr const char* kRateLimit = "MTG_RATE";
inline constexpr const char* kControl = "MTG_CONTROL";
inline constexpr const char* kError = "MTG_ERROR";
inline constexpr const char* kSceneRequest = "MTG_SCENE_REQ";
inline constexpr const char* kSceneSummary = "MTG_SCENE_SUMMARY";
inline constexpr const char* kTaskSetRequest = "MTG_TASKSET_REQ";
inline constexpr const char* kTaskSetSummary = "MTG_TASKSET_SUMMARY";

/// The request channel of renderer `pool_index` of a host's pool (core/render/render_pool.h):
/// kRenderRequest for 0, so a pool of one talks as a lone renderer did; "MTG_RENDER_REQ_<k>"
/// after, so each renderer wakes only for its own requests (bus/channel_filter.h).
std::string render_request_channel(int pool_index);
/// The role (heartbeats, process names) of renderer `pool_index`: "renderer", "renderer-1", ...
std::string renderer_role(int pool_index);
/// The pool index a renderer's role names; nullopt for any other role.
std::optional<int> renderer_index(const std::string& role);

/// The channel of the lease messages a coordinator sends to the worker of session
/// `worker_session` (grant, release, revoke): "MTG_LEASE_<session>".
std::string lease_channel(const std::string& worker_session);

/// Per-episode streams: one fixed channel each, the episode in the header (docs/bus.md
/// "Channels" says why not one channel per episode).
enum class EpisodeStream { kObservation, kAction, kState, kJudge };

/// e.g. episode_channel(kObservation) == "MTG_OBS".
const char* episode_channel(EpisodeStream stream);
/// Whether `channel` is that stream's channel.
bool is_episode_channel(const std::string& channel, EpisodeStream stream);

}  // namespace mtg::bus
