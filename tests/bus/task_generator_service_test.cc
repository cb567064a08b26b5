// The task-generator service as a real process on this test's own bus.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <optional>

#include "bus/bus.h"
#include "bus/channels.h"
#include "bus/header.h"
#include "bus/url.h"
#include "core/tasks/task_db.h"
#include "mtg/run_control_t.hpp"
#include "mtg/task_set_request_t.hpp"
#include "mtg/task_set_summary_t.hpp"
#include "tests/support/graph_fixtures.h"
#include "tests/support/process.h"

namespace mtg {
namespace {

TEST(TaskGeneratorService, AnswersRequestsSurvivesBadOnesAndShutsDown) {
  testing::FixtureDataset fx;
  testing::two_tables(fx);
  bus::Bus bus(bus::kDefaultUrl);
  std::optional<mtg::task_set_summary_t> reply;
  bus.subscribe<mtg::task_set_summary_t>(bus::kTaskSetSummary,
                                         [&](const std::string&, const mtg::task_set_summary_t& m) { reply = m; });
  testing::ChildProcess service({testing::bin("mtg_task_generator"), "--data", fx.root().string(), "--profile", "none"},
                                (fx.root() / "service.log").string());
  bus::HeaderStamper stamp("", "test");
  auto ask = [&](const std::string& id, const std::string& levels, const std::string& out) {
    mtg::task_set_request_t req{};
    req.header = stamp.next();
    req.request_id = id;
    req.scene = "two_tables";
    req.levels = levels;
    req.seed = 3;
    req.config_json = R"({"l3_count": 20})";
    req.out_path = out;
    reply.reset();
    // The service may still be starting: repeat the request until it answers.
    for (int i = 0; i < 100 && !reply; ++i) {
      bus.publish(bus::kTaskSetRequest, req);
      bus.handle_until([&] { return reply.has_value() && reply->request_id == id; }, 300);
    }
    return reply;
  };
  const auto good = ask("r1", "1,2,3", (fx.root() / "t.sqlite").string());
  ASSERT_TRUE(good.has_value());
  EXPECT_TRUE(good->ok) << good->error;
  EXPECT_GT(good->total, 50);
  EXPECT_EQ(good->level_counts[3], 0);
  EXPECT_EQ(static_cast<long>(tasks::read_tasks(fx.root() / "t.sqlite").size()), good->total);

  const auto bad = ask("r2", "1,7", (fx.root() / "u.sqlite").string());
  ASSERT_TRUE(bad.has_value());
  EXPECT_FALSE(bad->ok);
  EXPECT_THAT(bad->error, ::testing::HasSubstr("unknown level '7'"));
  EXPECT_FALSE(std::filesystem::exists(fx.root() / "u.sqlite"));

  const auto again = ask("r3", "4", (fx.root() / "v.sqlite").string());
  ASSERT_TRUE(again.has_value());
  EXPECT_TRUE(again->ok) << again->error;

  mtg::run_control_t stop{};
  stop.header = stamp.next();
  stop.command = "shutdown";
  stop.target = "task_generator";
  bus.publish(bus::kControl, stop);
  EXPECT_EQ(service.wait(5000), 0);
}

}  // namespace
}  // namespace mtg
