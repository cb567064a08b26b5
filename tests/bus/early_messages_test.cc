// Messages that overtake their episode's start: held, then handled when the start comes. udpm keeps
// no order across senders, so the scene-graph service's first observation can reach an agent
// before the orchestrator's start (bus/early_messages.h).

#include "bus/early_messages.h"

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "agents/common/agent_host.h"
#include "bus/bus.h"
#include "bus/channels.h"
#include "bus/header.h"
#include "bus/observation_packing.h"
#include "mtg/agent_action_t.hpp"
#include "mtg/episode_start_t.hpp"
#include "mtg/observation_t.hpp"
#include "mtg/state_update_t.hpp"

namespace mtg::bus {
namespace {

mtg::header_t header(std::int64_t episode, int attempt, std::int64_t seq = 0, const std::string& run = "run") {
  mtg::header_t h{};
  h.run_id = run;
  h.episode_id = episode;
  h.attempt = attempt;
  h.seq = seq;
  h.sender = "test";
  h.schema_version = kSchemaVersion;
  return h;
}

mtg::state_update_t state(std::int64_t episode, int attempt, std::int64_t seq) {
  mtg::state_update_t m{};
  m.header = header(episode, attempt, seq);
  return m;
}

TEST(EarlyMessages, AStartTakesItsAttemptsMessagesInOrderAndForgetsItsOtherAttempts) {
  EarlyMessages<mtg::state_update_t> early(16);
  early.hold(state(1, 0, 0));
  early.hold(state(2, 0, 0));
  early.hold(state(1, 1, 0));
  early.hold(state(1, 1, 1));
  const auto taken = early.take(header(1, 1));
  ASSERT_EQ(taken.size(), 2u);
  EXPECT_EQ(taken[0].header.seq, 0);
  EXPECT_EQ(taken[1].header.seq, 1);
  EXPECT_EQ(early.size(), 1u) << "episode 1's attempt 0 is gone with it, episode 2 waits";
  EXPECT_TRUE(early.take(header(2, 0, 0, "another run")).empty()) << "runs are told apart";
  EXPECT_EQ(early.take(header(2, 0)).size(), 1u);
  EXPECT_EQ(early.size(), 0u);
}

TEST(EarlyMessages, HoldsABoundedNumberDroppingTheOldest) {
  EarlyMessages<mtg::state_update_t> early(16);
  for (std::size_t i = 0; i < 26; ++i) early.hold(state(static_cast<std::int64_t>(i), 0, 0));
  EXPECT_EQ(early.size(), 16u);
  EXPECT_TRUE(early.take(header(0, 0)).empty()) << "the oldest went";
  EXPECT_EQ(early.take(header(10, 0)).size(), 1u);
}

// Replies "0" to every observation.
class Zero final : public agents::Policy {
 public:
  agents::AgentReply reply(const mtg::episode_start_t&, const mtg::observation_t&) override {
    agents::AgentReply r;
    r.raw = "0";
    return r;
  }
};

// An agent on an in-process bus: what it answers.
class AgentOnBus : public ::testing::Test {
 protected:
  AgentOnBus() : bus_("memq://"), stamp_("run", "agent:test"), host_(bus_, stamp_, "zero", std::make_unique<Zero>(), "run") {
    bus_.subscribe<mtg::agent_action_t>(episode_channel(EpisodeStream::kAction),
                                        [this](const std::string&, const mtg::agent_action_t& a) {
                                          actions_.push_back(a.header.episode_id);
                                        });
  }
  void start(std::int64_t episode, const std::string& agent) {
    mtg::episode_start_t s{};
    s.header = header(episode, 0);
    s.agent = agent;
    bus_.publish(kEpisodeStart, s);
  }
  void observe(std::int64_t episode, int step, bool done = false) {
    mtg::observation_t o{};
    o.header = header(episode, 0, step);
    o.step = step;
    o.done = done;
    o.actions.push_back({"0", "done"});
    o.n_actions = 1;
    bus_.publish(episode_channel(EpisodeStream::kObservation), o);
  }
  std::vector<std::int64_t> answered() {
    while (bus_.handle_once(0)) {
    }
    return std::exchange(actions_, {});
  }

  Bus bus_;
  HeaderStamper stamp_;
  agents::AgentHost host_;
  std::vector<std::int64_t> actions_;
};

TEST_F(AgentOnBus, AnObservationThatOvertakesItsStartIsAnsweredWhenTheStartComes) {
  observe(5, 0);
  EXPECT_TRUE(answered().empty());
  start(5, "zero");
  EXPECT_EQ(answered(), std::vector<std::int64_t>{5});
  observe(5, 1);
  EXPECT_EQ(answered(), std::vector<std::int64_t>{5}) << "then as usual";
}

TEST_F(AgentOnBus, OnlyAnAttemptsFirstObservationWaitsForItsStart) {
  observe(9, 1);  // a later step cannot come first: it needs this agent's answer (a stray copy)
  start(9, "zero");
  EXPECT_TRUE(answered().empty());
}

TEST_F(AgentOnBus, AnotherAgentsEpisodesAreNeitherAnsweredNorHeld) {
  start(6, "someone else");
  observe(6, 0);
  observe(7, 0);  // its start (also someone else's) comes after
  start(7, "someone else");
  EXPECT_TRUE(answered().empty());
  start(8, "zero");
  observe(8, 0);
  EXPECT_EQ(answered(), std::vector<std::int64_t>{8});
  EXPECT_EQ(host_.in_flight(), 1);
}


// Observations come packed (schema 7): the policy gets each as it was made; one that refers to a
// step the agent never received is answered at once with an error, so the episode runs again
// instead of waiting out its time-out.
class Seeing final : public agents::Policy {
 public:
  explicit Seeing(std::vector<mtg::observation_t>* seen) : seen_(seen) {}
  agents::AgentReply reply(const mtg::episode_start_t&, const mtg::observation_t& obs) override {
    seen_->push_back(obs);
    agents::AgentReply r;
    r.raw = "0";
    return r;
  }

 private:
  std::vector<mtg::observation_t>* seen_;
};

mtg::observation_t made_at(int step) {
  mtg::observation_t o{};
  o.header = header(1, 0, step);
  o.step = step;
  o.step_limit = 15;
  o.task_text = "Put the cup from table_1_platform_0 on the shelf.";
  o.text = "You are standing at the front side of platform table_1_platform_0 (l1). Your hand is empty. You have used " +
           std::to_string(step) + " of 15 steps.";
  o.actions = {{"0", "call_end: finish the task now"}, {"l1", "go to platform 1: table_1_platform_0"}};
  if (step % 2 == 1) o.actions.insert(o.actions.begin() + 1, {"o1", "pick up object 1"});
  o.n_actions = static_cast<int32_t>(o.actions.size());
  return o;
}

std::vector<std::uint8_t> bytes_of(const mtg::observation_t& o) {
  std::vector<std::uint8_t> b(static_cast<std::size_t>(o.getEncodedSize()));
  o.encode(b.data(), 0, static_cast<int>(b.size()));
  return b;
}

TEST(AgentOnPackedBus, ThePolicyGetsObservationsWholeAndOneReferringToALostStepIsAnErrorAtOnce) {
  Bus bus("memq://");
  HeaderStamper stamp("run", "agent:test");
  std::vector<mtg::observation_t> seen;
  agents::AgentHost host(bus, stamp, "seeing", std::make_unique<Seeing>(&seen), "run");
  std::vector<mtg::agent_action_t> actions;
  bus.subscribe<mtg::agent_action_t>(episode_channel(EpisodeStream::kAction),
                                     [&](const std::string&, const mtg::agent_action_t& a) { actions.push_back(a); });
  auto pump = [&] {
    while (bus.handle_once(0)) {
    }
  };
  mtg::episode_start_t s{};
  s.header = header(1, 0);
  s.agent = "seeing";
  bus.publish(kEpisodeStart, s);
  WordsCodec codec;
  WordsPacker packer;
  for (int step = 0; step < 3; ++step) {
    mtg::observation_t packed = made_at(step);
    packer.pack(packed, codec);
    bus.publish(episode_channel(EpisodeStream::kObservation), packed);
    pump();
  }
  ASSERT_EQ(seen.size(), 3u);
  for (int step = 0; step < 3; ++step) {
    EXPECT_EQ(bytes_of(seen[static_cast<std::size_t>(step)]), bytes_of(made_at(step))) << "step " << step;
  }
  ASSERT_EQ(actions.size(), 3u);
  EXPECT_TRUE(actions[2].error.empty());
  mtg::observation_t lost = made_at(3);
  packer.pack(lost, codec);  // never reaches the agent
  mtg::observation_t next = made_at(4);
  packer.pack(next, codec);
  bus.publish(episode_channel(EpisodeStream::kObservation), next);
  pump();
  EXPECT_EQ(seen.size(), 3u) << "the policy is not asked about what cannot be read";
  ASSERT_EQ(actions.size(), 4u);
  EXPECT_EQ(actions[3].step, 4);
  EXPECT_NE(actions[3].error.find("unreadable observation"), std::string::npos) << actions[3].error;
  EXPECT_NE(actions[3].error.find("step 3"), std::string::npos) << actions[3].error;
}

}  // namespace
}  // namespace mtg::bus
