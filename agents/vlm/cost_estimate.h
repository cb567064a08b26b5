#pragma once
// What a run of model agents will cost and how long it will take, before the first call
// (docs/vlm.md, "Cost before spending"). Pure arithmetic over the questions each episode asks
// (prompt_walk.h builds them from the real templates and observations): the conversation's
// growth with history_steps and history_images, each provider's rule for what an image costs,
// max_output_tokens as the most a call can answer, the price table and the rate limits.
//
// Each episode is figured twice: a model that solves it (its oracle plan, the final "0"
// included) and a model that never finishes (the step limit). The expected figure is halfway
// between the two: neither end is known before the run, and a model that fails usually does so
// somewhere between them (it ends with "0" too early, or wanders until the limit).

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "agents/vlm/model_spec.h"
#include "agents/vlm/prices.h"
#include "agents/vlm/settings.h"

namespace mtg::vlm {

/// One question of an episode, as far as its cost goes.
struct StepPrompt {
  std::int64_t user_chars = 0;   // the step template filled in (step_text)
  std::int64_t reply_chars = 0;  // the answer the history keeps (the oracle's key)
  int images = 0;                // images sent with the question (image_roles applied)
};

/// The questions of one episode: the system text and those of a model that solves it.
struct EpisodePrompts {
  std::int64_t system_chars = 0;
  std::vector<StepPrompt> solved;  // one per call, the last answered "0"
  int step_limit = 15;             // the episode's (calls of a model that never finishes)
};

struct EpisodeToEstimate {
  std::string agent;  // the model spec
  EpisodePrompts prompts;
};

struct EstimateInput {
  std::vector<EpisodeToEstimate> episodes;
  VlmSettings settings;
  PriceTable prices;
  bool images = true;  // the run renders images
  int image_width = 640;  // as rendered, before image_max_side
  int image_height = 480;
  std::string prompt_version;
  /// Episodes whose figures are another task's of the same scene and level (tasks not walked:
  /// too many, or their scene could not be loaded here).
  std::int64_t stand_ins = 0;
  /// Episodes left out: no task of any scene they could stand in for was walked.
  std::int64_t not_estimated = 0;
  std::string not_estimated_why;
};

/// The estimate as JSON: per agent and in total, for "low" (solves it), "expected" and "high"
/// (never finishes): calls, images, input_tokens, output_tokens (at most), cost_usd (list
/// price; 0 and price_known false for a model the table lacks), hours (null: no rate limit);
/// per agent also expected_episode_cost_usd. @throws mtg::Error for a malformed model spec.
nlohmann::json estimate_run(const EstimateInput& input);

/// The estimate for a person: one block per agent and a total, then what is approximated.
std::string estimate_text(const nlohmann::json& estimate);

// The parts, for tests.

/// The size an image is sent at: shrunk so its longer side is at most `max_side` (0 = as is),
/// as images_to_send shrinks it.
std::pair<int, int> sent_image_size(int width, int height, int max_side);

/// Input tokens of one image of `width` x `height` as sent, by the provider's rule: OpenAI (and
/// OpenAI-compatible servers) 85 at low detail, else 85 + 170 per 512-px tile after fitting in
/// 2048 x 2048 and bringing the shorter side down to 768; Anthropic width * height / 750 after
/// bringing the longer side down to 1568; Gemini 258 up to 384 x 384, else 258 per 768-px tile.
int image_tokens(Provider provider, const std::string& detail, int width, int height);

/// What one call sends: characters of text (system, kept turns, answers) and images.
struct CallSize {
  std::int64_t chars = 0;
  int images = 0;
};

/// The calls of an episode whose questions are `steps`, as Conversation windows them: the last
/// history_steps earlier steps (0 = all) with their answers, images on the newest
/// history_images steps only.
std::vector<CallSize> call_sizes(std::int64_t system_chars, const std::vector<StepPrompt>& steps, int history_steps,
                                 int history_images);

/// The questions of a model that never finishes: those of the solved episode, then as many as
/// the step limit leaves, each the mean of the solved episode's questions after the first (the
/// first carries the look-alike hint and close-ups; a one-step episode repeats its only one).
std::vector<StepPrompt> never_ending_steps(const EpisodePrompts& prompts);

/// Tokens of `chars` characters of text: 4 characters a token, as the rate gate counts them.
inline std::int64_t text_tokens(std::int64_t chars) { return chars / 4; }

}  // namespace mtg::vlm
