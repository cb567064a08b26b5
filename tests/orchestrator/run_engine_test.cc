// The run engine over a scripted launcher: what it does with retries when slots vanish (a lost
// host takes its slots with it) and when an agent stops while retries wait. No processes, no bus.

#include "orchestrator/run/run_engine.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <functional>
#include <map>
#include <set>

#include "orchestrator/remote/run_announcement.h"
#include "orchestrator/run/launcher.h"
#include "orchestrator/run/run_plan.h"
#include "orchestrator/run/results_db.h"
#include "tests/support/fixture_dataset.h"

namespace mtg::orchestrator {
namespace {

// Runs attempts on `capacity` slots; each poll() calls `script` once with what is in flight.
class ScriptedLauncher final : public Launcher {
 public:
  using Script = std::function<void(ScriptedLauncher&, LaunchSink&)>;
  explicit ScriptedLauncher(Script script) : script_(std::move(script)) {}

  std::vector<AdoptedAttempt> open() override { return {}; }
  int free_slots() const override { return capacity - static_cast<int>(in_flight.size()); }
  int next_attempt(bus::EpisodeId) const override { return 0; }
  void launch(const EpisodeLaunch& l) override {
    const auto key = std::make_pair(l.start.header.episode_id, static_cast<int>(l.start.header.attempt));
    ASSERT_GT(free_slots(), 0) << "launched without a free slot";
    launched.push_back(key);
    in_flight.insert(key);
  }
  void drop(bus::EpisodeId id, int attempt) override { in_flight.erase({id.value(), attempt}); }
  void poll(int, LaunchSink& sink) override {
    ++polls;
    script_(*this, sink);
  }
  void close() override {}
  int restarts() const override { return 0; }

  // The attempt ends with a verdict (success) or is lost without one.
  void finish(std::pair<std::int64_t, int> key, LaunchSink& sink) {
    in_flight.erase(key);
    sink.on_result(success(key), "host", nullptr);
  }
  // A successful verdict on the attempt `key`.
  static mtg::episode_result_t success(std::pair<std::int64_t, int> key) {
    mtg::episode_result_t m{};
    m.header.episode_id = key.first;
    m.header.attempt = key.second;
    m.success = true;
    m.ip = 1.0;
    m.stage = "done";
    m.cause = "";
    return m;
  }
  void lose(std::pair<std::int64_t, int> key, LaunchSink& sink) {
    in_flight.erase(key);
    sink.on_failure(bus::EpisodeId(key.first), key.second, "host lost");
  }

  int capacity = 2;
  int polls = 0;
  std::set<std::pair<std::int64_t, int>> in_flight;
  std::vector<std::pair<std::int64_t, int>> launched;

 private:
  Script script_;
};

struct Fixture {
  testing::FixtureDataset fx;
  RunPlan plan;
  std::map<std::string, tasks::Task> tasks;

  explicit Fixture(int episodes) {
    plan.run_id = "engine-test";
    plan.agents = {"oracle"};
    plan.parallel = 0;
    plan.max_attempts = 3;
    plan.episode_timeout_s = 600;
    tasks::Task t;
    t.id = "s/L1/000000";
    t.scene = "s";
    t.type = "surface";
    t.goal = nlohmann::json::object();
    tasks[t.id] = t;
    for (int i = 0; i < episodes; ++i) plan.episodes.push_back({bus::EpisodeId(i), t.id, "oracle", 7});
  }
  RunSummary run(Launcher& launcher, const Budget& budget = {}) {
    EngineOptions options;
    options.progress = false;
    options.budget = budget;
    return run_plan_with(plan, fx.root(), tasks, launcher, options);
  }
};

// The attempt ends with a verdict whose answers cost `spent_usd`.
void finish_paid(ScriptedLauncher& l, std::pair<std::int64_t, int> key, double spent_usd, LaunchSink& sink) {
  l.in_flight.erase(key);
  mtg::episode_result_t m = ScriptedLauncher::success(key);
  m.model_calls = 3;
  m.cost_usd = spent_usd;
  m.spent_usd = spent_usd;
  sink.on_result(m, "host", nullptr);
}

TEST(RunEngine, ARetryWithoutAFreeSlotWaitsAndGoesBeforeNewEpisodes) {
  Fixture f(3);
  ScriptedLauncher launcher([](ScriptedLauncher& l, LaunchSink& sink) {
    if (l.polls == 1) {
      // One of two hosts is lost with episode 0 on it: its slot goes too.
      l.capacity = 1;
      l.lose({0, 0}, sink);
      return;
    }
    if (!l.in_flight.empty()) l.finish(*l.in_flight.begin(), sink);
  });
  const RunSummary summary = f.run(launcher);
  EXPECT_EQ(summary.completed, 3);
  EXPECT_EQ(summary.retries, 1);
  const std::vector<std::pair<std::int64_t, int>> order = {{0, 0}, {1, 0}, {0, 1}, {2, 0}};
  EXPECT_EQ(launcher.launched, order) << "the retry waited for a slot and went before episode 2";
  std::map<std::int64_t, int> stored;
  for (const auto& row : read_results(f.fx.root() / "results.sqlite")) {
    EXPECT_EQ(stored.count(row.episode_id.value()), 0u) << "episode " << row.episode_id << " stored twice";
    stored[row.episode_id.value()] = row.attempt;
  }
  EXPECT_EQ(stored, (std::map<std::int64_t, int>{{0, 1}, {1, 0}, {2, 0}}));
}

TEST(RunEngine, RetriesWaitInTheOrderTheyFailed) {
  Fixture f(3);
  ScriptedLauncher launcher([](ScriptedLauncher& l, LaunchSink& sink) {
    if (l.polls == 1) {
      l.capacity = 0;  // every host lost, episode 2 first, then 0 and 1
      for (const auto& key : {std::make_pair<std::int64_t, int>(2, 0), {0, 0}, {1, 0}}) l.lose(key, sink);
      return;
    }
    if (l.polls < 4) return;
    l.capacity = 1;  // one host back
    if (!l.in_flight.empty()) l.finish(*l.in_flight.begin(), sink);
  });
  launcher.capacity = 3;  // all three start at once
  const RunSummary summary = f.run(launcher);
  EXPECT_EQ(summary.completed, 3);
  ASSERT_EQ(launcher.launched.size(), 6u);
  const std::vector<std::pair<std::int64_t, int>> retries(launcher.launched.begin() + 3, launcher.launched.end());
  EXPECT_EQ(retries, (std::vector<std::pair<std::int64_t, int>>{{2, 1}, {0, 1}, {1, 1}}));
}

TEST(RunEngine, AnAgentThatStopsTakesItsWaitingRetriesWithIt) {
  Fixture f(2);
  ScriptedLauncher launcher([](ScriptedLauncher& l, LaunchSink& sink) {
    if (l.polls == 1) {
      l.capacity = 0;
      l.lose({0, 0}, sink);  // both lost with every slot: their retries wait
      l.lose({1, 0}, sink);
      return;
    }
    if (l.polls == 2) sink.on_agent_stopped("oracle", "quota exhausted");
  });
  const RunSummary summary = f.run(launcher);
  EXPECT_EQ(summary.completed, 0);
  EXPECT_EQ(summary.not_run, 2);
  EXPECT_EQ(launcher.launched.size(), 2u) << "no retry was sent after the agent stopped";
  EXPECT_EQ(summary.stopped_agents.count("oracle"), 1u);
}

// Episodes the infrastructure gave up on are stored without a verdict (status "error"); the next
// invocation on the folder runs them again and their rows take the verdicts. Scored ones stay.
TEST(RunEngine, AResumeRunsAgainTheEpisodesGivenUpAndKeepsTheScoredOnes) {
  Fixture f(3);
  f.plan.max_attempts = 1;
  ScriptedLauncher failing([](ScriptedLauncher& l, LaunchSink& sink) {
    if (l.in_flight.empty()) return;
    const auto key = *l.in_flight.begin();
    if (key.first == 1) {
      l.finish(key, sink);
    } else {
      l.lose(key, sink);
    }
  });
  failing.capacity = 1;
  const RunSummary first = f.run(failing);
  EXPECT_EQ(first.errors, 2);
  std::map<std::int64_t, std::string> status;
  for (const auto& row : read_results(f.fx.root() / "results.sqlite")) status[row.episode_id.value()] = row.status;
  EXPECT_EQ(status, (std::map<std::int64_t, std::string>{{0, "error"}, {1, "scored"}, {2, "error"}}));

  ScriptedLauncher working([](ScriptedLauncher& l, LaunchSink& sink) {
    if (!l.in_flight.empty()) l.finish(*l.in_flight.begin(), sink);
  });
  const RunSummary resumed = f.run(working);
  EXPECT_EQ(resumed.already_done, 1);
  EXPECT_EQ(resumed.completed, 2);
  const std::vector<std::pair<std::int64_t, int>> order = {{0, 0}, {2, 0}};
  EXPECT_EQ(working.launched, order) << "only the episodes given up ran again";
  const auto rows = read_results(f.fx.root() / "results.sqlite");
  ASSERT_EQ(rows.size(), 3u);
  for (const auto& row : rows) EXPECT_EQ(row.status, "scored") << "episode " << row.episode_id;

  ScriptedLauncher idle([](ScriptedLauncher&, LaunchSink&) {});
  EXPECT_EQ(f.run(idle).already_done, 3);
  EXPECT_TRUE(idle.launched.empty()) << "a scored episode never runs again";
}

// --max-cost: an episode in flight counts at the estimate's figure until one has finished, then at
// the run's average; once spent plus in flight reaches the cap nothing more starts, what waits is
// left without a row, and a resume with a higher cap runs it.
TEST(RunEngine, ABudgetStopsNewEpisodesAndAResumeWithAHigherCapRunsTheRest) {
  Fixture f(6);
  auto paying = [](ScriptedLauncher& l, LaunchSink& sink) {
    if (!l.in_flight.empty()) finish_paid(l, *l.in_flight.begin(), 0.25, sink);
  };
  ScriptedLauncher first(paying);
  first.capacity = 2;
  Budget budget;
  budget.max_cost_usd = 1.0;
  budget.expected_episode_cost_usd = {{"oracle", 0.30}};
  // 0 and 1 start at 0.30 each; then each finished one costs 0.25 and the average takes over:
  // 0 done (0.25 + 0.25 in flight) starts 2; 1 done (0.50 + 0.25) starts 3, and 0.50 + 0.50
  // reaches the cap: 4 and 5 are not started.
  const RunSummary capped = f.run(first, budget);
  const std::vector<std::pair<std::int64_t, int>> order = {{0, 0}, {1, 0}, {2, 0}, {3, 0}};
  EXPECT_EQ(first.launched, order);
  EXPECT_EQ(capped.completed, 4) << "what was in flight finished";
  EXPECT_EQ(capped.not_started, 2);
  EXPECT_EQ(capped.budget_stop,
            "budget: $0.5000 spent + $0.5000 in flight reached --max-cost $1.00; 2 episode(s) not started; run the "
            "same command again with a higher --max-cost to go on");
  EXPECT_EQ(read_results(f.fx.root() / "results.sqlite").size(), 4u) << "no row for an episode not started";

  // The same cap again: what the run spent (results.sqlite) already reaches it.
  ScriptedLauncher again(paying);
  const RunSummary still = f.run(again, budget);
  EXPECT_TRUE(again.launched.empty());
  EXPECT_EQ(still.not_started, 2);
  EXPECT_THAT(still.budget_stop, ::testing::HasSubstr("$1.00 spent + $0.00 in flight reached --max-cost $1.00"));

  // A higher cap runs the rest, and says nothing about a budget.
  budget.max_cost_usd = 2.0;
  ScriptedLauncher rest(paying);
  const RunSummary finished = f.run(rest, budget);
  EXPECT_EQ(finished.already_done, 4);
  EXPECT_EQ(finished.completed, 2);
  EXPECT_TRUE(finished.budget_stop.empty());
  EXPECT_EQ(finished.not_started, 0);
  EXPECT_EQ(read_results(f.fx.root() / "results.sqlite").size(), 6u);
}

// Without a cap, or with one never reached, the engine runs everything as before.
TEST(RunEngine, ACapNeverReachedChangesNothing) {
  Fixture f(3);
  ScriptedLauncher l([](ScriptedLauncher& l2, LaunchSink& sink) {
    if (!l2.in_flight.empty()) finish_paid(l2, *l2.in_flight.begin(), 0.25, sink);
  });
  Budget budget;
  budget.max_cost_usd = 100.0;
  const RunSummary summary = f.run(l, budget);
  EXPECT_EQ(summary.completed, 3);
  EXPECT_TRUE(summary.budget_stop.empty());
}

// How the run's graphs read platforms travels with the run: plan.json keeps it (a plan written
// before says nothing and ran whole surfaces), and the announcement gives it to every worker.
TEST(RunPlatformRules, ThePlanAndTheAnnouncementCarryThem) {
  RunPlan plan;
  plan.run_id = "r";
  plan.platform_rules = graph::PlatformRules::kWholeSurface;
  nlohmann::json j = plan.to_json();
  EXPECT_EQ(j.at("platform_rules"), "whole_surface");
  EXPECT_EQ(RunPlan::from_json(j, "plan.json").platform_rules, graph::PlatformRules::kWholeSurface);
  j["platform_rules"] = "reached_and_seen";
  EXPECT_EQ(RunPlan::from_json(j, "plan.json").platform_rules, graph::PlatformRules::kReachedAndSeen);
  j.erase("platform_rules");
  EXPECT_EQ(RunPlan::from_json(j, "plan.json").platform_rules, graph::PlatformRules::kWholeSurface);
  j["platform_rules"] = "open";
  EXPECT_THROW((void)RunPlan::from_json(j, "plan.json"), Error);
  for (const graph::PlatformRules rules : {graph::PlatformRules::kWholeSurface, graph::PlatformRules::kReachedAndSeen}) {
    RuntimeConfig c;
    c.platform_rules = rules;
    EXPECT_EQ(remote::announced_config(remote::announcement(c, {})).platform_rules, rules);
  }
  mtg::run_info_t odd = remote::announcement(RuntimeConfig{}, {});
  odd.platform_rules = 7;
  EXPECT_THROW((void)remote::announced_config(odd), Error);
}

}  // namespace
}  // namespace mtg::orchestrator
