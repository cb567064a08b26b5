#pragma once
// What an agent's answers cost: telemetry that travels beside the verdict and is never part of it.
// One answer's figures (AnswerUsage: agent -> agent_action_t) add up to an episode's
// (EpisodeUsage: judge -> episode_result_t -> results.sqlite), and episodes add up to a run's
// (the report); bus/convert moves them
// across the bus, so the figures are copied in exactly one place per boundary.

#include <cstdint>
#include <string>

namespace mtg::episode {

struct AnswerUsage {
  int input_tokens = 0;
  int output_tokens = 0;
  int images_sent = 0;
  double cost_usd = 0.0;    // list price of the answer (also for a cache hit)
  double latency_ms = 0.0;  // wall time of the call
  bool cache_hit = false;   // answered without asking the provider
};

struct EpisodeUsage {
  std::int64_t input_tokens = 0;
  std::int64_t output_tokens = 0;
  std::int64_t images_sent = 0;
  std::int64_t model_calls = 0;  // answers from a model (cached or not)
  std::int64_t cache_hits = 0;
  double cost_usd = 0.0;      // list price of the answers used (equal on a cached rerun)
  double spent_usd = 0.0;     // what was really paid (cache hits cost nothing)
  double latency_ms = 0.0;    // summed call time
  std::string prompt_version; // "" for built-in agents

  /// Adds one answer; `from_model` is false for built-in agents (no call, nothing spent).
  void add(const AnswerUsage& answer, bool from_model, const std::string& answer_prompt_version) {
    input_tokens += answer.input_tokens;
    output_tokens += answer.output_tokens;
    images_sent += answer.images_sent;
    cost_usd += answer.cost_usd;
    latency_ms += answer.latency_ms;
    if (from_model) {
      ++model_calls;
      cache_hits += answer.cache_hit ? 1 : 0;
      spent_usd += answer.cache_hit ? 0.0 : answer.cost_usd;
    }
    if (!answer_prompt_version.empty()) prompt_version = answer_prompt_version;
  }

  /// Adds another episode's figures (a run's total); the prompt version is the last one given.
  void add(const EpisodeUsage& other) {
    input_tokens += other.input_tokens;
    output_tokens += other.output_tokens;
    images_sent += other.images_sent;
    model_calls += other.model_calls;
    cache_hits += other.cache_hits;
    cost_usd += other.cost_usd;
    spent_usd += other.spent_usd;
    latency_ms += other.latency_ms;
    if (!other.prompt_version.empty()) prompt_version = other.prompt_version;
  }
};

}  // namespace mtg::episode
