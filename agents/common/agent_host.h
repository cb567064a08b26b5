#pragma once
// Runs a Policy on the bus: serves the episodes whose episode_start names this agent, answers
// each observation once (per episode, attempt and step), parses the reply against the offered
// keys and publishes an agent_action_t. The policy gets each observation whole, as the scene
// graph made it: its words unpacked and every image by reference filled in. The agent sees only
// episode starts and observations (the built-in oracle also its plans: Policy::reads_answers).
//
// Built-in policies answer in the bus thread (workers = 0). Model policies wait seconds for an
// API, so they answer on `workers` threads, several episodes at once; the bus thread publishes
// their actions from poll(). Only the bus thread touches the bus.

#include <condition_variable>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "agents/common/policy.h"
#include "bus/bus.h"
#include "bus/early_messages.h"
#include "bus/episode_table.h"
#include "bus/header.h"
#include "bus/observation_packing.h"

namespace mtg::agents {

class AgentHost {
 public:
  AgentHost(bus::Bus& bus, bus::HeaderStamper& stamp, std::string agent_spec, std::unique_ptr<Policy> policy,
            std::string run_id = "", int workers = 0);
  /// Stops the workers (after their current call returns).
  ~AgentHost();
  AgentHost(const AgentHost&) = delete;
  AgentHost& operator=(const AgentHost&) = delete;

  int in_flight() const { return static_cast<int>(episodes_.size()); }
  /// Publishes the actions the workers finished. Call from the bus thread between messages.
  void poll();

 private:
  struct Episode {
    int attempt = 0;  // set by the table
    mtg::episode_start_t start{};
    int last_step = -1;
    bus::ObservationReader reader;  // makes the packed observations whole (schema 7)
  };
  struct Other {  // an episode another agent serves: its observations are not for this one
    int attempt = 0;  // set by the table
  };
  struct Job {
    mtg::episode_start_t start;
    mtg::observation_t observation;
  };
  struct Done {
    mtg::observation_t observation;
    AgentReply reply;
  };
  void on_start(const mtg::episode_start_t& start);
  void on_observation(const mtg::observation_t& obs);
  void work();
  void publish(const mtg::observation_t& obs, const AgentReply& reply);

  bus::Bus& bus_;
  bus::HeaderStamper& stamp_;
  std::string spec_;
  std::unique_ptr<Policy> policy_;
  std::string run_id_;
  using Episodes = bus::EpisodeTable<Episode>;
  Episodes episodes_;
  bus::EpisodeTable<Other> others_{4096};  // never told when they end: bounded
  // First observations that came before their start. An observation may carry images (about
  // 1 MB): few are kept, and only an attempt's first (a later one needs this agent's answer).
  bus::EarlyMessages<mtg::observation_t> early_{16};
  bool stop_reported_ = false;
  bus::WordsCodec codec_;  // the bus thread's

  std::mutex mutex_;
  std::condition_variable work_ready_;
  std::deque<Job> jobs_;
  std::deque<Done> done_;
  bool stopping_ = false;
  std::vector<std::thread> workers_;
};

}  // namespace mtg::agents
