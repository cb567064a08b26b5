#pragma once
// Runs a Policy on the bus: serves the episodes whose episode_start names this agent, answers
// each observation once (per episode, attempt and step), parses the reply against the offered
// keys and publishes an agent_action_t. The agent sees only episode starts and observations.

#include <map>
#include <memory>
#include <string>
#include <utility>

#include "agents/common/policy.h"
#include "bus/bus.h"
#include "bus/header.h"

namespace mtg::agents {

class AgentHost {
 public:
  AgentHost(bus::Bus& bus, bus::HeaderStamper& stamp, std::string agent_spec, std::unique_ptr<Policy> policy,
            std::string run_id = "");
  int in_flight() const { return static_cast<int>(episodes_.size()); }

 private:
  struct Episode {
    mtg::episode_start_t start{};
    int last_step = -1;
  };
  void on_start(const mtg::episode_start_t& start);
  void on_observation(const mtg::observation_t& obs);

  bus::Bus& bus_;
  bus::HeaderStamper& stamp_;
  std::string spec_;
  std::unique_ptr<Policy> policy_;
  std::string run_id_;
  std::map<std::pair<std::string, std::int64_t>, Episode> episodes_;
};

}  // namespace mtg::agents
