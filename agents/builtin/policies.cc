#include "agents/builtin/policies.h"

#include <lcm/lcm-cpp.hpp>

#include <filesystem>
#include <map>

#include "bus/channels.h"
#include "bus/convert.h"
#include "bus/recording.h"
#include "core/util/error.h"
#include "core/util/json_file.h"
#include "core/util/rng.h"
#include "mtg/agent_action_t.hpp"

namespace mtg::agents {
namespace {

namespace fs = std::filesystem;

// Plays each task's oracle plan, which only it receives (MTG_EPISODE_TRUTH).
class OraclePolicy : public Policy {
 public:
  bool reads_answers() const override { return true; }
  void answer(const mtg::episode_truth_t& truth) override {
    const std::pair<std::string, std::int64_t> key{truth.header.run_id, truth.header.episode_id};
    // Bounded all the same: an answer whose start never came goes once thousands came after it.
    if (plans_.size() >= kPlansKept && plans_.count(key) == 0) plans_.erase(plans_.begin());
    Plan& p = plans_[key];
    if (p.attempt > truth.header.attempt) return;
    p = Plan{truth.header.attempt, truth.oracle_plan};
  }
  AgentReply reply(const mtg::episode_start_t& start, const mtg::observation_t& obs) override {
    AgentReply r;
    r.model = "oracle";
    const auto it = plans_.find({start.header.run_id, start.header.episode_id});
    if (it == plans_.end() || it->second.attempt != start.header.attempt) {
      r.error = "oracle: no plan arrived for episode " + std::to_string(start.header.episode_id) + " attempt " +
                std::to_string(start.header.attempt);
      return r;
    }
    const auto& plan = it->second.keys;
    r.raw = obs.step < static_cast<int>(plan.size()) ? plan[static_cast<std::size_t>(obs.step)] : "0";
    return r;
  }
  void end(const mtg::episode_start_t& start) override {
    const auto it = plans_.find({start.header.run_id, start.header.episode_id});
    if (it != plans_.end() && it->second.attempt == start.header.attempt) plans_.erase(it);
  }
  void not_mine(const mtg::episode_start_t& start) override { plans_.erase({start.header.run_id, start.header.episode_id}); }

 private:
  struct Plan {
    int attempt = -1;
    std::vector<std::string> keys;
  };
  static constexpr std::size_t kPlansKept = 4096;
  std::map<std::pair<std::string, std::int64_t>, Plan> plans_;  // the latest attempt per episode
};

class RandomPolicy : public Policy {
 public:
  AgentReply reply(const mtg::episode_start_t& start, const mtg::observation_t& obs) override {
    AgentReply r;
    r.model = "random";
    if (obs.actions.empty()) {
      r.raw = "0";
      return r;
    }
    Rng rng(derive_seed(static_cast<std::uint64_t>(start.seed), static_cast<std::uint64_t>(obs.step)));
    r.raw = obs.actions[rng.uniform_index(obs.actions.size())].key;
    return r;
  }
};

// Replies recorded in a run's LCM logs: per episode, the answers of its last recorded attempt.
class ReplayPolicy : public Policy {
 public:
  explicit ReplayPolicy(const fs::path& run_dir) {
    const auto damage = bus::for_each_recorded_event(run_dir, [this](const lcm::LogEvent& ev) {
      if (!bus::is_episode_channel(ev.channel, bus::EpisodeStream::kAction)) return;
      mtg::agent_action_t a{};
      if (a.decode(ev.data, 0, ev.datalen) < 0) return;
      recorded_[a.header.episode_id][a.header.attempt][a.step] = a;
    });
    if (!damage.empty()) damaged_ = " (the recording is damaged: " + bus::describe(damage.front()) + ")";
  }

  AgentReply reply(const mtg::episode_start_t& start, const mtg::observation_t& obs) override {
    AgentReply r;
    r.provider = "replay";
    // The recorded run has another run id; episodes are matched by id.
    const auto it = recorded_.find(start.header.episode_id);
    if (it == recorded_.end()) {
      r.error = "replay: no recorded answers for episode " + std::to_string(start.header.episode_id) + damaged_;
      return r;
    }
    const auto& last_attempt = it->second.rbegin()->second;
    const auto step = last_attempt.find(obs.step);
    if (step == last_attempt.end()) {
      r.error = "replay: no recorded answer for episode " + std::to_string(start.header.episode_id) + " step " +
                std::to_string(obs.step) + damaged_;
      return r;
    }
    const mtg::agent_action_t& a = step->second;
    r.raw = a.raw_reply;
    r.error = a.error;
    r.provider = a.provider;
    r.model = a.model;
    r.prompt_version = a.prompt_version;
    r.request = a.request;  // what the recorded run sent, so the replayed run shows it too
    r.usage = bus::answer_usage(a);
    r.usage.cache_hit = true;  // nothing was asked of a provider
    return r;
  }

 private:
  using Steps = std::map<int, mtg::agent_action_t>;
  std::map<std::int64_t, std::map<int, Steps>> recorded_;  // episode -> attempt -> step -> answer
  std::string damaged_;  // "" or why answers may be missing
};

class ScriptPolicy : public Policy {
 public:
  explicit ScriptPolicy(const std::string& file) {
    const nlohmann::json doc = read_json_file(file);
    const JsonField replies = JsonField(doc, file).at("replies");
    for (std::size_t i = 0; i < replies.size(); ++i) replies_.push_back(replies.at(i).as_string());
  }
  AgentReply reply(const mtg::episode_start_t&, const mtg::observation_t& obs) override {
    AgentReply r;
    r.model = "script";
    r.raw = obs.step < static_cast<int>(replies_.size()) ? replies_[static_cast<std::size_t>(obs.step)] : "0";
    return r;
  }

 private:
  std::vector<std::string> replies_;
};

}  // namespace

bool is_builtin_agent(const std::string& spec) {
  return spec == kOracleAgent || spec == "random" || spec.rfind("replay:", 0) == 0 || spec.rfind("script:", 0) == 0;
}

std::unique_ptr<Policy> make_builtin_policy(const std::string& spec) {
  if (spec == kOracleAgent) return std::make_unique<OraclePolicy>();
  if (spec == "random") return std::make_unique<RandomPolicy>();
  if (spec.rfind("replay:", 0) == 0) return std::make_unique<ReplayPolicy>(spec.substr(7));
  if (spec.rfind("script:", 0) == 0) return std::make_unique<ScriptPolicy>(spec.substr(7));
  throw Error("unknown agent '" + spec + "' (built-in: oracle, random, replay:<run dir>, script:<file>)");
}

}  // namespace mtg::agents
