// The task database as files: what two runs given the same output, and a killed run, leave.

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/util/host_name.h"
#include "tests/support/graph_fixtures.h"
#include "tests/support/process.h"
#include "tests/support/text_file.h"

namespace mtg {
namespace {

namespace fs = std::filesystem;

// Files next to `file` whose names start with its name and ".partial".
std::vector<std::string> partials_of(const fs::path& file) {
  std::vector<std::string> out;
  const std::string prefix = file.filename().string() + ".partial";
  for (const auto& e : fs::directory_iterator(file.parent_path())) {
    const std::string name = e.path().filename().string();
    if (name.compare(0, prefix.size(), prefix) == 0) out.push_back(name);
  }
  return out;
}

class TaskFiles : public ::testing::Test {
 protected:
  void SetUp() override { testing::two_tables(fx_); }

  std::vector<std::string> tasks_to(const fs::path& out) const {
    return {testing::bin("mtg"), "tasks", "--data", fx_.root().string(), "--scene", "two_tables", "--profile", "none",
            "--levels", "1,2,3", "--l3-count", "400", "--jobs", "1", "--out", out.string(), "--jsonl",
            out.string() + ".jsonl"};
  }
  int run_alone(const fs::path& out) const {
    return testing::ChildProcess(tasks_to(out), (fx_.root() / "log.txt").string()).wait(120000);
  }

  testing::FixtureDataset fx_;
};

// Each run builds its own partial file, so neither writes into the other's: both finish, and
// the file is what one run alone writes.
TEST_F(TaskFiles, TwoRunsGivenTheSameOutputBothFinishWithTheBytesOfOne) {
  const fs::path alone = fx_.root() / "alone.sqlite", both = fx_.root() / "both.sqlite";
  ASSERT_EQ(run_alone(alone), 0) << testing::read_text(fx_.root() / "log.txt");
  testing::ChildProcess first(tasks_to(both), (fx_.root() / "first.txt").string());
  testing::ChildProcess second(tasks_to(both), (fx_.root() / "second.txt").string());
  EXPECT_EQ(first.wait(120000), 0) << testing::read_text(fx_.root() / "first.txt");
  EXPECT_EQ(second.wait(120000), 0) << testing::read_text(fx_.root() / "second.txt");
  EXPECT_EQ(testing::read_text(both), testing::read_text(alone));
  EXPECT_EQ(testing::read_text(both.string() + ".jsonl"), testing::read_text(alone.string() + ".jsonl"));
  EXPECT_TRUE(partials_of(both).empty()) << ::testing::PrintToString(partials_of(both));
}

// A killed run's partial (and SQLite journal) goes with the next run of the same output; a
// partial of a process that still runs is another run's, and stays.
TEST_F(TaskFiles, AKilledRunsPartialGoesWithTheNextRunAndALiveRunsStays) {
  const fs::path out = fx_.root() / "tasks.sqlite";
  const pid_t gone = ::fork();
  if (gone == 0) ::_exit(0);
  ASSERT_GT(gone, 0);
  ASSERT_EQ(::waitpid(gone, nullptr, 0), gone);
  const std::string prefix = out.string() + ".partial-" + host_name() + "-";
  const fs::path killed = prefix + std::to_string(gone);
  const fs::path live = prefix + std::to_string(::getpid());
  for (const fs::path& p : {killed, fs::path(killed.string() + "-journal"), live, fs::path(out.string() + ".partial")}) {
    std::ofstream(p) << "left over";
  }
  ASSERT_EQ(run_alone(out), 0) << testing::read_text(fx_.root() / "log.txt");
  EXPECT_TRUE(fs::exists(out));
  EXPECT_EQ(partials_of(out), std::vector<std::string>{live.filename().string()});
}

}  // namespace
}  // namespace mtg
