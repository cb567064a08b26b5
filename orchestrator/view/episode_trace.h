#pragma once
// One episode as the viewer shows it, decoded from its recorded messages: the task, every step
// (what the agent saw, what it answered, what the judge noted), the verdict with its cause in
// plain words. The goal and the oracle plan are kept apart (episode_truth): the page shows them
// only when asked, as the agent never saw them.

#include <cstdint>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "bus/episode_id.h"
#include "bus/truth_seal.h"
#include "orchestrator/view/recording_index.h"

namespace mtg::orchestrator::view {

/// The attempts recorded for the episode, in order.
std::vector<int> recorded_attempts(const std::vector<RecordedMessage>& messages);

/// {episode_id, attempt, attempts, task{task_id, scene, level, task_type, text}, agent, seed,
///  step_limit, render, steps[{step, done, observation{text, hint, actions[{key, description}],
///  images[{index, role, encoding, width, height, bytes}]}, action{raw_reply, parsed_key, format_ok,
///  error, provider, model, input_tokens, output_tokens, cost_usd, latency_ms, cache_hit}|null,
///  request (model agents: the request as sent, in full, episode::resolve_requests)|null,
///  reply{text, parsed_key, meaning (the offered action's description)}|null,
///  judge[{kind, subtask, milestone, ip, text}]}], result{...verdict, stage_text, cause_text}|null,
///  errors[{source, severity, message}]}. `attempt` < 0 picks the last recorded attempt.
/// @throws mtg::Error naming the channel of a message that does not decode.
nlohmann::json episode_trace(bus::EpisodeId episode_id, const std::vector<RecordedMessage>& messages, int attempt);

/// Sets "url" on every image of `episode` (an episode_trace): the observations' images and the
/// images each model request names; null where the recording holds no bytes.
void link_images(nlohmann::json& episode, const std::function<std::string(int step, int index)>& url_of);

/// {task_id, goal (parsed), oracle_plan[], identify (parsed)} of the attempt, or null.
/// Sealed answers are opened with `answers` (the run folder's key).
nlohmann::json episode_truth(const std::vector<RecordedMessage>& messages, int attempt,
                             const bus::RecordedTruths& answers);

struct RecordedImage {
  std::string encoding;  // "png" or "jpeg"
  std::vector<std::uint8_t> bytes;
};
/// The `index`-th image of the observation at `step` of the attempt, if recorded with its bytes.
std::optional<RecordedImage> observation_image(const std::vector<RecordedMessage>& messages, int attempt, int step,
                                               int index);
/// Every image of the attempt recorded with its bytes, by (step, index), in one pass.
std::map<std::pair<int, int>, RecordedImage> observation_images(const std::vector<RecordedMessage>& messages,
                                                                int attempt);

}  // namespace mtg::orchestrator::view
