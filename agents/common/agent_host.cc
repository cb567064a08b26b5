#include "agents/common/agent_host.h"

#include "bus/channels.h"
#include "bus/convert.h"
#include "bus/error_events.h"
#include "core/episode/reply_parser.h"
#include "core/util/error.h"
#include "core/util/log.h"
#include "mtg/agent_action_t.hpp"
#include "mtg/error_event_t.hpp"

namespace mtg::agents {

constexpr std::size_t kMaxRawReply = 64 * 1024;

AgentHost::AgentHost(bus::Bus& bus, bus::HeaderStamper& stamp, std::string agent_spec, std::unique_ptr<Policy> policy,
                     std::string run_id, int workers)
    : bus_(bus), stamp_(stamp), spec_(std::move(agent_spec)), policy_(std::move(policy)), run_id_(std::move(run_id)) {
  bus_.subscribe<mtg::episode_start_t>(bus::kEpisodeStart,
                                       [this](const std::string&, const mtg::episode_start_t& m) { on_start(m); });
  bus_.subscribe<mtg::observation_t>(bus::episode_channel(bus::EpisodeStream::kObservation),
                                     [this](const std::string&, const mtg::observation_t& m) { on_observation(m); });
  // Answers reach only a policy that plays them (the built-in oracle): no model adapter ever
  // subscribes to them.
  if (policy_->reads_answers()) {
    bus_.subscribe<mtg::episode_truth_t>(bus::kEpisodeTruth, [this](const std::string&, const mtg::episode_truth_t& m) {
      if (run_id_.empty() || m.header.run_id == run_id_) policy_->answer(m);
    });
  }
  for (int i = 0; i < workers; ++i) workers_.emplace_back([this] { work(); });
}

AgentHost::~AgentHost() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  work_ready_.notify_all();
  for (auto& t : workers_) t.join();
}

void AgentHost::on_start(const mtg::episode_start_t& start) {
  if (!run_id_.empty() && start.header.run_id != run_id_) return;
  const std::vector<mtg::observation_t> early = early_.take(start.header);
  if (start.agent != spec_) {
    if (others_.is_new_attempt(start.header)) others_.start(start.header, Other{});
    policy_->not_mine(start);
    return;
  }
  if (!episodes_.is_new_attempt(start.header)) return;  // a duplicate or an older attempt
  if (const Episode* older = episodes_.find(Episodes::key_of(start.header)); older != nullptr) {
    policy_->end(older->start);
  }
  others_.erase(Episodes::key_of(start.header));
  episodes_.start(start.header, Episode{0, start, -1, {}});
  policy_->begin(start);
  for (const mtg::observation_t& obs : early) on_observation(obs);
}

void AgentHost::on_observation(const mtg::observation_t& obs) {
  Episode* found = episodes_.current(obs.header);
  if (found == nullptr) {
    if (others_.current(obs.header) != nullptr) {
      if (obs.done) others_.erase(Episodes::key_of(obs.header));
    } else if (obs.step == 0 && (run_id_.empty() || obs.header.run_id == run_id_) &&
               episodes_.is_new_attempt(obs.header) && others_.is_new_attempt(obs.header)) {
      early_.hold(obs);  // its start is still on its way (bus/early_messages.h)
    }
    return;
  }
  Episode& e = *found;
  if (obs.done) {
    policy_->end(e.start);
    episodes_.erase(Episodes::key_of(obs.header));
    stamp_.forget_episode(bus::episode_of(obs.header));
    return;
  }
  if (obs.step <= e.last_step) return;  // answered already (a duplicate observation)
  e.last_step = obs.step;
  mtg::observation_t whole;
  try {
    whole = e.reader.whole(obs, codec_);
  } catch (const Error& unreadable) {
    // It refers to what never came (or came damaged): the attempt cannot go on as the scene
    // graph sees it, so say so at once; the orchestrator runs the episode again.
    log::error(unreadable.what());
    AgentReply reply;
    reply.error = std::string("unreadable observation: ") + unreadable.what();
    publish(obs, reply);
    return;
  }
  if (workers_.empty()) {
    publish(whole, policy_->reply(e.start, whole));
    return;
  }
  {
    std::lock_guard lock(mutex_);
    jobs_.push_back({e.start, std::move(whole)});
  }
  work_ready_.notify_one();
}

void AgentHost::work() {
  for (;;) {
    Job job;
    {
      std::unique_lock lock(mutex_);
      work_ready_.wait(lock, [this] { return stopping_ || !jobs_.empty(); });
      if (stopping_) return;
      job = std::move(jobs_.front());
      jobs_.pop_front();
    }
    AgentReply reply;
    try {
      reply = policy_->reply(job.start, job.observation);
    } catch (const std::exception& e) {
      reply.error = e.what();
    }
    std::lock_guard lock(mutex_);
    done_.push_back({std::move(job.observation), std::move(reply)});
  }
}

void AgentHost::poll() {
  std::deque<Done> done;
  {
    std::lock_guard lock(mutex_);
    done.swap(done_);
  }
  for (const Done& d : done) publish(d.observation, d.reply);
}

void AgentHost::publish(const mtg::observation_t& obs, const AgentReply& reply) {
  if (reply.stop_agent && !stop_reported_) {
    // Once per process: the orchestrator stops giving this agent episodes and says why.
    stop_reported_ = true;
    log::error("agent stopped: " + reply.error);
    mtg::error_event_t ev = bus::agent_stopped_event(spec_, reply.error);
    ev.header = stamp_.next(bus::episode_of(obs.header), obs.header.attempt, "error");
    ev.header.run_id = obs.header.run_id;
    bus_.publish(bus::kError, ev);
  }
  mtg::agent_action_t a{};
  a.header = stamp_.next(bus::episode_of(obs.header), obs.header.attempt, "action");
  a.header.run_id = obs.header.run_id;
  a.step = obs.step;
  a.raw_reply = reply.raw.substr(0, kMaxRawReply);
  a.error = reply.error;
  if (reply.error.empty()) {
    std::vector<std::string> offered;
    for (const auto& option : obs.actions) offered.push_back(option.key);
    const episode::ParsedReply parsed = episode::parse_reply(reply.raw, offered);
    a.parsed_key = parsed.key;
    a.format_ok = parsed.ok;
  }
  a.provider = reply.provider;
  a.model = reply.model;
  bus::set_usage(a, reply.usage);
  a.prompt_version = reply.prompt_version;
  a.request = reply.request;
  bus_.publish(bus::episode_channel(bus::EpisodeStream::kAction), a);
}

}  // namespace mtg::agents
