// A long run through one set of processes (`mtg bench soak`): no process of it may grow with the
// number of episodes (issue 37; docs/runtime.md, "What each process keeps"). 50,000 text-only
// episodes of the fixture's tasks, repeated; the bench's own samples of every process's RSS.

#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "tests/support/fixture_dataset.h"
#include "tests/support/graph_fixtures.h"
#include "tests/support/process.h"

namespace mtg {
namespace {

TEST(SoakTest, FiftyThousandEpisodesLeaveEveryProcessAtTheSizeItHadAfterTheFirstTenThousand) {
  testing::FixtureDataset fx;
  const std::string db = testing::two_tables_task_db(fx);
  const auto json_file = fx.root() / "soak.json";
  const std::string log = (fx.root() / "soak.log").string();
  testing::ChildProcess soak({testing::bin("mtg"), "--log-level", "warn", "bench", "soak", "--episodes", "50000",
                              "--tasks", db, "--data", fx.root().string(), "--levels", "1,2,3", "--work",
                              (fx.root() / "soak").string(), "--every", "10", "--json", json_file.string()},
                             log);
  const int status = soak.wait(600000);
  std::ifstream said_in(log);
  const std::string said((std::istreambuf_iterator<char>(said_in)), {});
  ASSERT_EQ(status, 0) << said;
  std::ifstream in(json_file);
  const auto out = nlohmann::json::parse(in);
  EXPECT_EQ(out["episodes"], 50000);
  EXPECT_EQ(out["retries"], 0) << said;
  // +10 MiB from 10,000 to 1,000,000 episodes is 0.4 MiB over these 40,000; RSS moves by whole
  // pages and allocator arenas, so a process passes within 1 MiB.
  const double bound = std::max(1.0, out["bound_mib"].get<double>());
  ASSERT_GE(out["growth_mib"].size(), 5u) << said;  // orchestrator, recorder, scene graph, judge, agents
  for (const auto& [role, mib] : out["growth_mib"].items()) {
    EXPECT_LE(mib.get<double>(), bound) << role << " grew with the episodes:\n" << said;
  }
  std::printf("%s", said.c_str());
}

}  // namespace
}  // namespace mtg
