// Suites end to end: `mtg suite make | info | verify` and `mtg run --suite` with real processes on
// the test's own bus; bad suites and other datasets refused in one line with nothing written; the
// suite kept in tests/data (made by an earlier version) still runs unchanged.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "core/tasks/suite.h"
#include "tests/support/run_fixture.h"
#include "tests/support/shipped_data.h"

namespace mtg {
namespace {

namespace fs = std::filesystem;

class SuiteRunTest : public testing::RunFixture {
 protected:
  std::string suite_file() const { return (fx_.root() / "suite.json").string(); }

  // From a task set made by `mtg tasks`, which records the files each scene was loaded from (the
  // fixture's own set, written in-process, has no fingerprint to check a dataset against).
  int make_suite(int per_level, const std::string& file) {
    const std::string set = (fx_.root() / "cli_tasks.sqlite").string();
    if (!fs::exists(set)) {
      const int made = mtg({testing::bin("mtg"), "tasks", "--data", fx_.root().string(), "--scene", "two_tables",
                            "--profile", "none", "--levels", "1,2,3", "--l3-count", "40", "--jobs", "1", "--out", set});
      if (made != 0) return made;
    }
    return mtg({testing::bin("mtg"), "suite", "make", "--tasks", set, "--per-level", std::to_string(per_level), "--seed",
                "5", "--name", "fixture", "--out", file});
  }

  std::vector<std::string> suite_run(const std::string& out, const std::string& suite) {
    return {testing::bin("mtg"), "run",     "--suite",           suite, "--agent", "oracle", "--parallel", "2",
            "--out",             (fx_.root() / out).string(), "--data", fx_.root().string(), "--profile", "none",
            "--episode-timeout", "5",       "--no-progress"};
  }
};

TEST_F(SuiteRunTest, ASuiteRunsExactlyItsTasksFromItsOwnCopy) {
  ASSERT_EQ(make_suite(4, suite_file()), 0) << log_text();
  const tasks::Suite suite = tasks::read_suite(suite_file());
  ASSERT_FALSE(suite.tasks.empty());
  ASSERT_EQ(mtg({testing::bin("mtg"), "suite", "verify", suite_file(), "--data", fx_.root().string(), "--profile", "none"}), 0)
      << log_text();
  EXPECT_NE(log_text().find("suite " + suite.id() + " verified"), std::string::npos) << log_text();
  ASSERT_EQ(mtg(suite_run("run", suite_file())), 0) << log_text();
  // Every task of the suite once, no other, each solved by the oracle.
  std::set<std::string> ran;
  for (const auto& r : results("run")) {
    ran.insert(r.task_id);
    EXPECT_TRUE(r.success) << r.task_id << " " << r.detail;
  }
  std::set<std::string> wanted;
  for (const auto& t : suite.tasks) wanted.insert(t.id);
  EXPECT_EQ(ran, wanted);
  // The run holds the suite's bytes and names it in its provenance.
  std::ifstream a(suite_file(), std::ios::binary), b(fx_.root() / "run" / "suite.json", std::ios::binary);
  std::stringstream sa, sb;
  sa << a.rdbuf();
  sb << b.rdbuf();
  EXPECT_EQ(sa.str(), sb.str());
  std::ifstream plan_in(fx_.root() / "run" / "plan.json");
  const nlohmann::json plan = nlohmann::json::parse(plan_in);
  EXPECT_EQ(plan["provenance"]["suite"]["id"], suite.id());
  EXPECT_EQ(plan["provenance"]["draw"]["kind"], "suite");
  EXPECT_EQ(plan["numbering"], "stable");  // tasks of this build's format: numbers stay put
  // The run no longer needs the file it was given: it resumes, and rejudges, from its copy.
  fs::remove(suite_file());
  EXPECT_EQ(mtg(suite_run("run", (fx_.root() / "run" / "suite.json").string())), 0) << log_text();
  EXPECT_EQ(mtg({testing::bin("mtg"), "rejudge", (fx_.root() / "run").string()}), 0) << log_text();
}

TEST_F(SuiteRunTest, BadSuitesAndOtherDatasetsAreRefusedInOneLineWithNothingWritten) {
  ASSERT_EQ(make_suite(3, suite_file()), 0) << log_text();
  std::ifstream in(suite_file(), std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string good = ss.str();
  auto refused = [&](const std::string& content, const std::vector<std::string>& extra, const std::string& words) {
    const std::string file = (fx_.root() / "bad.json").string();
    std::ofstream(file, std::ios::binary | std::ios::trunc) << content;
    auto args = suite_run("bad_run", file);
    args.insert(args.end(), extra.begin(), extra.end());
    EXPECT_EQ(mtg(args), 1) << log_text();
    EXPECT_NE(last_line().find(words), std::string::npos) << "expected '" << words << "' in: " << log_text();
    EXPECT_FALSE(fs::exists(fx_.root() / "bad_run")) << "a refused run left its folder";
  };
  std::string edited = good;
  edited.replace(edited.find("\"text\":\"") + 8, 1, "X");
  refused(edited, {}, "does not match its digest");
  refused(good.substr(0, good.size() - 40), {}, "cut short");
  std::string future = good;
  future.replace(future.find("mtg-suite/1"), 11, "mtg-suite/2");
  refused(future, {}, "not one this mtg reads");
  refused(good, {"--limit", "2"}, "--limit goes with a task set (--tasks tasks.sqlite)");
  // Another dataset: one of the scene's files changed. The line names it.
  const tasks::Suite suite = tasks::read_suite(suite_file());
  ASSERT_FALSE(suite.dataset.at("two_tables").files.empty());
  const std::string changed = suite.dataset.at("two_tables").files.begin()->first;
  std::ofstream(fx_.root() / changed, std::ios::app) << "\n";
  refused(good, {}, changed);
  EXPECT_NE(last_line().find("differs"), std::string::npos) << log_text();
}

TEST_F(SuiteRunTest, AFolderOfOneSuiteRefusesAnother) {
  ASSERT_EQ(make_suite(2, suite_file()), 0) << log_text();
  const std::string other = (fx_.root() / "other.json").string();
  ASSERT_EQ(make_suite(3, other), 0) << log_text();
  ASSERT_EQ(mtg(suite_run("run", suite_file())), 0) << log_text();
  EXPECT_EQ(mtg(suite_run("run", other)), 1);
  EXPECT_NE(last_line().find("not of suite fixture@"), std::string::npos) << log_text();
}

// A frozen suite run whole with the oracle on the shipped data: its results and its plan.
struct OracleRun {
  std::vector<orchestrator::EpisodeRow> rows;
  nlohmann::json plan;
};

// `name` keeps two tests' folders apart; `extra` goes to `mtg run` as given.
OracleRun run_with_oracle(const fs::path& suite_file, const std::string& name, const std::vector<std::string>& extra) {
  const fs::path out = fs::temp_directory_path() / (name + "_" + std::to_string(::getpid()));
  fs::remove_all(out);
  const std::string log = out.string() + ".log";
  std::vector<std::string> argv = {testing::bin("mtg"), "--log-level", "warn", "run", "--suite", suite_file.string(),
                                   "--agent", "oracle", "--parallel", "4"};
  argv.insert(argv.end(), extra.begin(), extra.end());
  argv.insert(argv.end(), {"--out", out.string(), "--data", testing::shipped_dataset()->root.string(), "--no-progress"});
  testing::ChildProcess run(argv, log);
  OracleRun result;
  const int rc = run.wait(300000);
  EXPECT_EQ(rc, 0) << std::ifstream(log).rdbuf();
  if (rc == 0) {
    result.rows = orchestrator::read_results(out / "results.sqlite");
    result.plan = nlohmann::json::parse(std::ifstream(out / "plan.json"));
  }
  fs::remove_all(out);
  fs::remove(log);
  return result;
}

// The suite in tests/data was made by an earlier version on the shipped apartments. Every later
// version must read it (same identity) and run it unchanged: the oracle solves every task.
TEST(FrozenSuite, TheKeptSuiteStillRunsUnchanged) {
  const fs::path file = fs::path(MTG_SOURCE_DIR) / "tests" / "data" / "suites" / "compat-v1.json";
  const tasks::Suite suite = tasks::read_suite(file);
  EXPECT_EQ(suite.id(), "compat-v1@095b43d5f9ab");
  MTG_REQUIRE_SHIPPED_DATA();
  const OracleRun run = run_with_oracle(file, "mtg_frozen_suite", {});
  ASSERT_FALSE(HasFailure());
  EXPECT_EQ(run.rows.size(), suite.tasks.size());
  for (const auto& r : run.rows) EXPECT_TRUE(r.success) << r.task_id << " " << r.detail;
  // Its later oracle keys count the release's numbering, and its runs keep it.
  EXPECT_EQ(run.plan.value("numbering", ""), "per_state");
}

// The shipped standard suite (1,200 tasks of mtg-tasks/2) runs as it was drawn: every task solved
// by the oracle. Its goals were planned on whole surfaces; a TV stand's floor cut to its opening
// (mtg-tasks/5) failed 14 of them, so its runs keep whole surfaces, said in the plan.
TEST(FrozenSuite, TheShippedStandardSuiteIsSolvedWhole) {
  const fs::path file = fs::path(MTG_SOURCE_DIR) / "core" / "tasks" / "suites" / "standard-replicacad.json";
  MTG_REQUIRE_SHIPPED_DATA();
  const tasks::Suite suite = tasks::read_suite(file);
  const OracleRun run = run_with_oracle(file, "mtg_standard_suite", {"--no-render"});
  ASSERT_FALSE(HasFailure());
  EXPECT_EQ(run.rows.size(), suite.tasks.size());
  int failed = 0;
  for (const auto& r : run.rows) {
    if (!r.success && ++failed <= 10) ADD_FAILURE() << r.task_id << " " << r.detail;
  }
  EXPECT_EQ(failed, 0);
  EXPECT_EQ(run.plan.value("platform_rules", ""), "whole_surface");
}

}  // namespace
}  // namespace mtg
