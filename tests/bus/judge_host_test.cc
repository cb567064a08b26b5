// The judge on an in-process bus (memq://): a first state update that overtakes its episode's
// start is judged once the start comes, not taken for a lost message (bus/early_messages.h).

#include "services/judge/judge_host.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "bus/bus.h"
#include "bus/channels.h"
#include "bus/convert.h"
#include "bus/header.h"
#include "core/tasks/generator.h"
#include "mtg/episode_result_t.hpp"
#include "mtg/episode_truth_t.hpp"
#include "tests/support/fixture_dataset.h"
#include "tests/support/graph_fixtures.h"

namespace mtg::services {
namespace {

mtg::header_t header(std::int64_t seq) {
  mtg::header_t h{};
  h.run_id = "run";
  h.episode_id = 1;
  h.attempt = 0;
  h.seq = seq;
  h.sender = "scene_graph:test";
  h.schema_version = bus::kSchemaVersion;
  return h;
}

TEST(JudgeOnBus, AStateUpdateThatOvertakesItsStartIsJudgedWhenTheStartComes) {
  testing::FixtureDataset fx;
  const auto built = testing::two_tables(fx);
  tasks::TaskOptions options;
  options.levels = {1, 2};
  const auto generated = tasks::generate_tasks(built.scene, built.graph, options);
  ASSERT_FALSE(generated.set.tasks.empty());
  const tasks::Task& task = generated.set.tasks.front();

  bus::Bus bus("memq://");
  bus::HeaderStamper stamp("run", "judge:test");
  graph::SceneCache scenes("none");
  JudgeHost judge(bus, stamp, scenes, "run");
  std::vector<mtg::episode_result_t> results;
  bus.subscribe<mtg::episode_result_t>(bus::kEpisodeResult, [&](const std::string&, const mtg::episode_result_t& r) {
    results.push_back(r);
  });

  mtg::state_update_t first{};  // the episode as it starts: nothing done yet
  first.header = header(0);
  first.side = -1;
  bus.publish(bus::episode_channel(bus::EpisodeStream::kState), first);  // before the start

  mtg::episode_truth_t truth = bus::truth_message(task);
  truth.header = header(0);
  truth.header.sender = "orchestrator:test";
  mtg::episode_start_t start{};
  start.header = truth.header;
  start.task = bus::to_message(task);
  start.agent = "oracle";
  start.step_limit = 15;
  start.data_dir = fx.root().string();
  bus.publish(bus::kEpisodeTruth, truth);
  bus.publish(bus::kEpisodeStart, start);

  mtg::state_update_t end = first;  // the agent ends the episode at once
  end.header = header(1);
  end.step = 1;
  end.key = "0";
  end.available = true;
  end.applied = true;
  end.done = true;
  end.end_reason = "call_end";
  bus.publish(bus::episode_channel(bus::EpisodeStream::kState), end);
  while (bus.handle_once(0)) {
  }

  ASSERT_EQ(results.size(), 1u);
  EXPECT_NE(results[0].cause, "transport_error") << results[0].detail;
  EXPECT_FALSE(results[0].success) << "ended before anything was moved";
}

}  // namespace
}  // namespace mtg::services
