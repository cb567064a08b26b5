#pragma once
// The scene-graph service's episodes: one world state per running episode (many at once), the
// paper's action rules applied to each agent answer, and the messages that follow: a state
// update for the judge (with how the action was applied) and the next observation.
//
// Identity is (run id, episode id, attempt): a new episode_start with a higher attempt replaces
// the old state; answers for another attempt or another step are stale and ignored, so a late
// or duplicated message never applies twice.

#include <chrono>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "bus/bus.h"
#include "bus/convert.h"
#include "bus/episode_join.h"
#include "bus/episode_table.h"
#include "bus/header.h"
#include "bus/observation_packing.h"
#include "core/episode/goals.h"
#include "core/episode/rules.h"
#include "core/episode/transcript.h"
#include "core/graph/scene_cache.h"
#include "core/render/close_ups.h"
#include "core/tasks/task.h"
#include "mtg/agent_action_t.hpp"
#include "mtg/episode_start_t.hpp"
#include "mtg/observation_t.hpp"
#include "mtg/render_request_t.hpp"
#include "mtg/render_result_t.hpp"

namespace mtg::services {

/// Test hook (MTG_FAULTS="drop_state:<step>,dup_state:<step>"): drop or duplicate the state
/// update of that step, in first attempts only, to exercise loss detection end to end.
struct FaultInjection {
  int drop_state_step = -1;
  int duplicate_state_step = -1;
  static FaultInjection from_env();
};

/// Images for episodes that ask for them (episode_start_t.render), from a renderer process.
struct ImageOptions {
  int width = 640;
  int height = 480;
  std::string encoding = "png";
  double timeout_s = 20.0;  // per request; one resend, then the observation goes without images
  /// The host's pool of renderers (core/render/render_pool.h): renderer k serves the channel
  /// bus::render_request_channel(k). Each episode keeps one renderer; a new one goes to the
  /// renderer holding the fewest.
  int renderers = 1;
};

class EpisodeHost {
 public:
  /// Subscribes to episode starts and truths, agent actions and render results of run `run_id`
  /// ("" = every run).
  EpisodeHost(bus::Bus& bus, bus::HeaderStamper& stamp, graph::SceneCache& scenes, std::string run_id,
              FaultInjection faults = {}, ImageOptions images = {});

  void on_start(const mtg::episode_start_t& start, const mtg::episode_truth_t& truth);
  void on_action(const mtg::agent_action_t& action);
  void on_render_result(const mtg::render_result_t& result);
  /// Resends or gives up on render requests that got no answer in time (liveness only: what the
  /// agent is told never depends on it unless the renderer is gone).
  void check_render_timeouts();
  /// Episodes currently held (a finished episode is dropped with its last observation).
  int in_flight() const { return static_cast<int>(episodes_.size()); }

 private:
  struct Episode {
    int attempt = 0;  // set by the table
    const graph::SceneGraph* graph = nullptr;
    bus::EpisodeTask task;
    episode::TaskConstraints constraints;
    episode::RuleOptions rules;
    episode::WorldState state;
    std::string hint;
    bool render = false;
    std::string data_dir;
    int held_number = 0;                // the held item's number where it was picked
    render::CloseUpsShown close_ups;    // the look-alike close-ups sent so far
    // An observation waiting for its images (request id = its step).
    bool awaiting_images = false;
    mtg::observation_t pending;
    mtg::render_request_t request;  // kept for the one resend
    std::chrono::steady_clock::time_point requested_at;
    bool resent = false;
    int renderer = -1;             // its renderer in the pool (-1: none asked yet)
    bool resent_on_restart = false;  // this request's one resend for a renderer's restart
    bus::WordsPacker words;  // what the next observation's words are packed against (docs/bus.md)
  };
  using Episodes = bus::EpisodeTable<Episode>;
  using Key = Episodes::Key;

  /// `step` (null for the initial state) adds how the action was applied.
  void publish_state(const Key& key, Episode& e, const episode::StateUpdate& u,
                     const episode::EpisodeStep* step = nullptr);
  void publish_observation(const Key& key, Episode& e);
  /// Sends the observation now, or asks the renderer to send it with the images.
  void send_observation(const Key& key, Episode& e, mtg::observation_t obs);
  /// The step's observation is out: sent here unless the renderer `published` it.
  void finish_observation(const Key& key, Episode& e, bool published = false);
  void report_error(const Key& key, int attempt, const std::string& message);
  /// A renderer's heartbeat: one with a new pid replaced a renderer that died, and the requests
  /// it held go to the new one.
  void on_renderer_beat(int index, int pid);
  /// The renderer for the episode's requests (chosen at its first).
  int renderer_of(Episode& e);
  void send_request(Episode& e);

  bus::Bus& bus_;
  bus::HeaderStamper& stamp_;
  graph::SceneCache& scenes_;
  std::string run_id_;
  FaultInjection faults_;
  ImageOptions images_;
  Episodes episodes_;
  bus::EpisodeJoin starts_;
  bus::WordsCodec codec_;
  std::vector<int> renderer_pids_;  // per pool index, the pid last heard (0: none yet)
};

}  // namespace mtg::services
