// Scores that mean something, on the shipped apt_0 over the bus: an agent that does nothing
// scores nothing on any level, and re-judging the recording gives every verdict again, field for
// field, over thousands of episodes of a do-nothing and a random agent.

#include <gtest/gtest.h>

#include <fstream>
#include <map>

#include "orchestrator/run/rejudge.h"
#include "orchestrator/run/results_db.h"
#include "tests/support/fixture_dataset.h"
#include "tests/support/process.h"
#include "tests/support/shipped_data.h"

namespace mtg {
namespace {

namespace fs = std::filesystem;

TEST(ShippedScores, DoingNothingScoresZeroAndRejudgeAgreesOnEveryEpisode) {
  MTG_REQUIRE_SHIPPED_DATA();
  testing::FixtureDataset scratch;
  const fs::path dir = scratch.root();
  const std::string log = (dir / "mtg.log").string();
  const std::string db = (dir / "apt_0.sqlite").string();
  ASSERT_EQ(testing::ChildProcess({testing::bin("mtg"), "tasks", "--scene", "apt_0", "--l3-count", "1000", "--out", db},
                                  log)
                .wait(300000),
            0);
  const fs::path nothing = dir / "nothing.json";
  std::ofstream(nothing) << R"({"replies": ["0"]})";
  const fs::path run = dir / "run";
  ASSERT_EQ(testing::ChildProcess({testing::bin("mtg"), "run", "--tasks", db, "--levels", "1,2,3,4", "--limit", "1000",
                                   "--parallel", "4", "--agent", "script:" + nothing.string(), "--agent", "random",
                                   "--out", run.string(), "--no-progress"},
                                  log)
                .wait(900000),
            0);
  const auto rows = orchestrator::read_results(run / "results.sqlite");
  std::map<std::pair<std::string, int>, int> episodes, successes;
  for (const auto& r : rows) {
    ASSERT_EQ(r.status, "scored") << r.task_id << ": " << r.detail;
    const std::string agent = r.agent.rfind("script:", 0) == 0 ? "nothing" : r.agent;
    episodes[{agent, r.level}] += 1;
    successes[{agent, r.level}] += r.success ? 1 : 0;
    if (agent == "nothing") {
      EXPECT_FALSE(r.success) << r.task_id << " is won by doing nothing";
      EXPECT_EQ(r.ip, 0.0) << r.task_id;
    }
  }
  for (const char* agent : {"nothing", "random"}) {
    for (int level = 1; level <= 4; ++level) {
      const auto key = std::make_pair(std::string(agent), level);
      // apt_0 has 653 Level 4 tasks since what they name must be clearly visible: all of them.
      EXPECT_GE(episodes[key], level == 4 ? 600 : 1000) << agent << " level " << level;
      std::printf("[ scores   ] %-8s level %d: %d / %d successes\n", agent, level, successes[key], episodes[key]);
    }
  }
  // One judge: the recording re-scored from the recorded answers alone gives the same verdict,
  // stage and cause for every episode.
  const orchestrator::RejudgeReport again = orchestrator::rejudge_run(run);
  EXPECT_EQ(again.identical, static_cast<std::int64_t>(rows.size()));
  for (std::size_t i = 0; i < again.differences.size() && i < 10; ++i) ADD_FAILURE() << again.differences[i];
}

}  // namespace
}  // namespace mtg
