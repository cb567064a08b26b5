#pragma once
// What an agent is: given the episode (its start message) and the current observation, a reply.
// Built-in agents reply with a key; model adapters reply with free text that the host parses.

#include <string>

#include "core/episode/usage.h"
#include "mtg/episode_start_t.hpp"
#include "mtg/episode_truth_t.hpp"
#include "mtg/observation_t.hpp"

namespace mtg::agents {

struct AgentReply {
  std::string raw;            // the reply text (a key, or a model's free text)
  std::string error;          // provider failure ("" if none): ends the episode
  std::string provider = "builtin";
  std::string model;
  episode::AnswerUsage usage;  // telemetry only
  std::string prompt_version; // "" for built-in agents
  std::string request;        // model agents: what was sent, agent_action_t.request ("" for built-in agents)
  bool stop_agent = false;    // the error ends this agent for the whole run (auth, quota, billing)
};

class Policy {
 public:
  virtual ~Policy() = default;
  /// Called once per episode attempt before its first observation.
  virtual void begin(const mtg::episode_start_t& /*start*/) {}
  /// May be called from several threads at once for different episodes (AgentHost workers);
  /// never twice at once for the same episode.
  virtual AgentReply reply(const mtg::episode_start_t& start, const mtg::observation_t& observation) = 0;
  /// Called once when the episode attempt ends (or is replaced by a newer attempt).
  virtual void end(const mtg::episode_start_t& /*start*/) {}
  /// Whether the policy is given episodes' answers (MTG_EPISODE_TRUTH, published before each
  /// start): the built-in oracle, which plays them, and no other agent.
  virtual bool reads_answers() const { return false; }
  virtual void answer(const mtg::episode_truth_t& /*truth*/) {}
  /// The episode of `start` is another agent's: forget its answer (every answer reaches the
  /// policy, so one kept for another agent's episode would stay for good).
  virtual void not_mine(const mtg::episode_start_t& /*start*/) {}
};

}  // namespace mtg::agents
